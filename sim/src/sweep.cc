#include "arttrack/sim/sweep.h"

#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/yaml_config.h"
#include "text_format.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::size_t kMaxAxisValues = 10000;

// Splits one CSV line (RFC 4180 quoting, no embedded newlines).
bool split_csv(const std::string& line, std::vector<std::string>& fields) {
  fields.clear();
  std::string cur;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cur += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  fields.push_back(cur);
  return !quoted;
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// ---- statistics ----

struct StatDef {
  std::string name;
  bool converged = false;
  bool rotation = false;
  int percentile = 0;  // 1, 25, 50, 75, 99; 0: convergence time
};

const std::vector<StatDef>& stat_defs() {
  static const std::vector<StatDef> defs = [] {
    std::vector<StatDef> d;
    for (bool converged : {false, true})
      for (bool rotation : {false, true})
        for (int p : {1, 25, 50, 75, 99})
          d.push_back({std::string(converged ? "converged_" : "") + "p" + std::to_string(p) +
                           (rotation ? "_rotation_rad" : "_translation_m"),
                       converged, rotation, p});
    d.push_back({"convergence_time_s", false, false, 0});
    return d;
  }();
  return defs;
}

double pick(const Percentiles& p, int percentile) {
  switch (percentile) {
    case 1:
      return p.p01;
    case 25:
      return p.p25;
    case 50:
      return p.p50;
    case 75:
      return p.p75;
    default:
      return p.p99;
  }
}

// ---- HTML helpers ----

// Viridis through five anchors, t in [0, 1].
std::string colour(double t) {
  static const double anchors[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  t = std::clamp(t, 0.0, 1.0) * 4;
  const int i = std::min(3, int(t));
  const double f = t - i;
  char buf[8];
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x",
                int(std::lround(anchors[i][0] + f * (anchors[i + 1][0] - anchors[i][0]))),
                int(std::lround(anchors[i][1] + f * (anchors[i + 1][1] - anchors[i][1]))),
                int(std::lround(anchors[i][2] + f * (anchors[i + 1][2] - anchors[i][2]))));
  return buf;
}

std::string short_value(double v) {
  if (std::isnan(v)) return "-";
  if (std::isinf(v)) return v > 0 ? "never" : "-inf";
  if (std::fabs(v) < 5e-4) return "0";
  if (std::fabs(v) >= 100) return text::format_g(std::round(v), 6);
  return text::format_g(v, 3);
}

// Colour scale of one statistic over all methods and cells.
struct Scale {
  double lo = 0, hi = 1;
  bool log = false;
  bool any = false;
  double t(double v) const {
    if (!any || hi <= lo) return 0.5;
    if (log) return (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
    return (v - lo) / (hi - lo);
  }
};

}  // namespace

// ---- statistics ----

const std::vector<std::string>& sweep_statistics() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const StatDef& d : stat_defs()) n.push_back(d.name);
    return n;
  }();
  return names;
}

void check_statistic_name(const std::string& name, const std::string& context) {
  for (const std::string& s : sweep_statistics())
    if (s == name) return;
  if (name == "p50_image_update_ms" || name == "p99_image_update_ms") return;
  throw InputError(context + ": unknown statistic '" + name +
                   "' (known: p1|p25|p50|p75|p99 _translation_m or _rotation_rad, with or "
                   "without converged_ before, convergence_time_s, p50_image_update_ms, "
                   "p99_image_update_ms)");
}

StatisticUnit statistic_unit(const std::string& statistic) {
  if (statistic.find("translation") != std::string::npos) return {"m", "mm", 1e3};
  if (statistic.find("rotation") != std::string::npos) return {"rad", "deg", 180.0 / M_PI};
  if (statistic.ends_with("_ms")) return {"ms", "ms", 1};
  return {"s", "s", 1};
}

double method_statistic(const MethodResult& m, const std::string& name) {
  if (name == "p50_image_update_ms") return m.timing.image_update_ms.p50;
  if (name == "p99_image_update_ms") return m.timing.image_update_ms.p99;
  for (const StatDef& d : stat_defs()) {
    if (d.name != name) continue;
    if (d.percentile == 0) return median_convergence_s(m.summary);
    const ErrorStats& e = d.converged ? m.summary.converged : m.summary.all;
    return pick(d.rotation ? e.rotation_rad : e.translation_m, d.percentile);
  }
  check_statistic_name(name, "statistic");
  return kNaN;
}

// ---- grid ----

GridAxis parse_grid_axis(const std::string& spec) {
  const std::string context = "--grid '" + spec + "'";
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(context + ": expected key=start:stop:step or key=v1,v2,...");
  GridAxis axis;
  axis.spec = spec;
  axis.key = text::trim(spec.substr(0, eq));
  if (axis.key.find_first_of(" \t=") != std::string::npos)
    throw InputError(context + ": the key '" + axis.key + "' contains a space");
  try {
    parse_key_path(axis.key);
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  const std::string rhs = spec.substr(eq + 1);
  if (text::trim(rhs).empty()) throw InputError(context + ": no values after '='");

  if (rhs.find(':') != std::string::npos) {
    std::vector<std::string> parts;
    std::stringstream in(rhs);
    for (std::string p; std::getline(in, p, ':');) parts.push_back(p);
    if (parts.size() != 3 || rhs.back() == ':')
      throw InputError(context + ": a range is start:stop:step (three numbers)");
    double v[3];
    const char* names[3] = {"start", "stop", "step"};
    for (int i = 0; i < 3; ++i)
      if (!text::parse_number(parts[i], v[i]))
        throw InputError(context + ": " + names[i] + " '" + text::trim(parts[i]) +
                         "' is not a finite number");
    const double start = v[0], stop = v[1], step = v[2];
    if (!(step > 0)) throw InputError(context + ": step must be > 0, not " + text::trim(parts[2]));
    if (stop < start)
      throw InputError(context + ": stop " + text::trim(parts[1]) + " is below start " +
                       text::trim(parts[0]));
    const double count = std::floor((stop - start) / step + 1e-6) + 1;
    if (count > double(kMaxAxisValues))
      throw InputError(context + ": gives " + text::format_g(count, 6) + " values, more than " +
                       std::to_string(kMaxAxisValues));
    for (long i = 0; i < long(count); ++i) {
      // Twelve digits drop the float noise of start + i step (0.30000000000000004).
      std::string text = text::format_g(start + double(i) * step, 12);
      if (!axis.values.empty() && text == axis.values.back())
        throw InputError(context + ": step is too small to tell values apart");
      axis.values.push_back(text);
    }
    return axis;
  }

  std::stringstream in(rhs);
  std::set<std::string> seen;
  for (std::string item; std::getline(in, item, ',');) {
    item = text::trim(item);
    if (item.empty()) throw InputError(context + ": an empty value in the list");
    try {
      YAML::Load(item);
    } catch (const YAML::Exception& e) {
      throw InputError(context + ": value '" + item + "' is not valid YAML: " + e.msg);
    }
    if (!seen.insert(item).second)
      throw InputError(context + ": value '" + item + "' is listed twice");
    axis.values.push_back(item);
  }
  if (rhs.back() == ',') throw InputError(context + ": an empty value in the list");
  return axis;
}

Shard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  const std::string context = "--shard '" + text + "'";
  double i = 0, n = 0;
  if (slash == std::string::npos || !text::parse_number(text.substr(0, slash), i) ||
      !text::parse_number(text.substr(slash + 1), n) || i != std::floor(i) || n != std::floor(n))
    throw InputError(context + ": expected I/N with whole numbers, e.g. 0/4");
  if (n < 1 || n > 1e6) throw InputError(context + ": N must be in 1..1000000");
  if (i < 0 || i >= n)
    throw InputError(context + ": I must be in 0.." + std::to_string(long(n) - 1));
  return {int(i), int(n)};
}

std::size_t SweepSpec::cell_count() const {
  std::size_t n = 1;
  for (const GridAxis& a : axes) n *= a.values.size();
  return n;
}

std::vector<std::size_t> SweepSpec::cell_coordinates(std::size_t cell) const {
  std::vector<std::size_t> c(axes.size());
  for (std::size_t a = axes.size(); a-- > 0;) {
    c[a] = cell % axes[a].values.size();
    cell /= axes[a].values.size();
  }
  return c;
}

std::vector<std::string> SweepSpec::cell_overrides(std::size_t cell) const {
  const std::vector<std::size_t> c = cell_coordinates(cell);
  std::vector<std::string> out;
  for (std::size_t a = 0; a < axes.size(); ++a)
    out.push_back(axes[a].key + "=" + axes[a].values[c[a]]);
  return out;
}

std::uint64_t cell_seed(const std::vector<std::string>& cell_overrides,
                        std::uint64_t scenario_seed) {
  std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a 64
  bool first = true;
  for (const std::string& o : cell_overrides) {
    if (!first) h = (h ^ std::uint64_t('\n')) * 0x100000001b3ULL;
    first = false;
    for (unsigned char c : o) h = (h ^ c) * 0x100000001b3ULL;
  }
  return splitmix64(h ^ splitmix64(scenario_seed)) & ((std::uint64_t(1) << 53) - 1);
}

void resolve_sweep(SweepSpec& spec) {
  if (spec.axes.empty()) throw InputError("sweep: give at least one --grid key=start:stop:step");
  for (std::size_t a = 0; a < spec.axes.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (spec.axes[a].key == spec.axes[b].key)
        throw InputError("--grid '" + spec.axes[a].spec + "': key '" + spec.axes[a].key +
                         "' is swept twice (also by '" + spec.axes[b].spec + "')");
  if (spec.runs < 0) throw InputError("--runs must be >= 1");
  if (spec.seed < -1) throw InputError("--seed must be >= 0");
  if (!(spec.fail_threshold_m > 0) || !std::isfinite(spec.fail_threshold_m))
    throw InputError("--fail-threshold-m must be a finite number > 0");
  const auto& stats = sweep_statistics();
  if (std::find(stats.begin(), stats.end(), spec.fail_statistic) == stats.end()) {
    check_statistic_name(spec.fail_statistic, "--fail-statistic");
    throw InputError("--fail-statistic: '" + spec.fail_statistic +
                     "' is a wall time, not reproducible; use an error statistic");
  }

  const Scenario base = load_scenario(spec.scenario, spec.overrides);
  spec.scenario_name = base.name;
  spec.scenario_seed = spec.seed >= 0 ? std::uint64_t(spec.seed) : base.seed;
  if (spec.runs == 0) spec.runs = base.runs;
  if (spec.methods.empty()) spec.methods = base.methods;
  for (std::size_t i = 0; i < spec.methods.size(); ++i) {
    parse_method(spec.methods[i], "--methods");
    for (std::size_t k = 0; k < i; ++k)
      if (spec.methods[i] == spec.methods[k])
        throw InputError("--methods: '" + spec.methods[i] + "' is listed twice");
  }

  // Every key must be one the scenario reads; a value it rejects only fails
  // its cells.
  for (const GridAxis& axis : spec.axes) {
    for (const std::string& v : axis.values) {
      std::vector<std::string> overrides = spec.overrides;
      overrides.push_back(axis.key + "=" + v);
      try {
        load_scenario(spec.scenario, overrides);
      } catch (const InputError& e) {
        const std::string what = e.what();
        if (what.find("is not a known key") != std::string::npos ||
            what.find("override '") != std::string::npos)
          throw InputError("--grid '" + axis.spec + "': " + what);
      }
    }
  }
}

CellResult run_sweep_cell(const SweepSpec& spec, std::size_t cell,
                          const std::function<void(const RunProgress&)>& progress) {
  CellResult r;
  r.cell = cell;
  const std::vector<std::string> cell_over = spec.cell_overrides(cell);
  r.seed = cell_seed(cell_over, spec.scenario_seed);
  const auto& stats = sweep_statistics();
  r.stats.assign(spec.methods.size(), std::vector<double>(stats.size(), kNaN));
  try {
    std::vector<std::string> overrides = spec.overrides;
    overrides.insert(overrides.end(), cell_over.begin(), cell_over.end());
    const Scenario scenario = load_scenario(spec.scenario, overrides);
    RunOptions options;
    options.runs = spec.runs;
    options.seed = (long long)r.seed;
    options.methods = spec.methods;
    options.progress = progress;
    options.frames_to_keep = 0;
    const ScenarioResult result = run_scenario(scenario, options);
    for (std::size_t m = 0; m < spec.methods.size(); ++m) {
      const MethodResult* mr = result.method(spec.methods[m]);
      if (!mr) throw InputError("the runner returned no result for " + spec.methods[m]);
      for (std::size_t s = 0; s < stats.size(); ++s)
        r.stats[m][s] = method_statistic(*mr, stats[s]);
    }
  } catch (const std::exception& e) {
    r.failed = true;
    r.message = text::one_line(e.what());
    if (r.message.empty()) r.message = "unknown error";
    for (auto& row : r.stats) std::fill(row.begin(), row.end(), kNaN);
  }
  return r;
}

// ---- CSV ----

namespace {

std::string csv_header(const SweepSpec& spec) {
  std::string h = "cell";
  for (const GridAxis& a : spec.axes) h += "," + text::csv_field(a.key);
  return h + ",method,statistic,value,seed,runs,status,message";
}

}  // namespace

void write_sweep_csv(std::ostream& out, const SweepSpec& spec,
                     const std::vector<CellResult>& cells) {
  const auto& stats = sweep_statistics();
  out << csv_header(spec) << '\n';
  for (const CellResult& c : cells) {
    const std::vector<std::size_t> coord = spec.cell_coordinates(c.cell);
    std::string prefix = std::to_string(c.cell);
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      prefix += ',';
      prefix += text::csv_field(spec.axes[a].values[coord[a]]);
    }
    std::string suffix = ",";
    suffix += std::to_string(c.seed);
    suffix += ',';
    suffix += std::to_string(spec.runs);
    suffix += c.failed ? ",failed," : ",ok,";
    if (c.failed) suffix += text::csv_field(c.message);
    for (std::size_t m = 0; m < spec.methods.size(); ++m)
      for (std::size_t s = 0; s < stats.size(); ++s)
        out << prefix << ',' << spec.methods[m] << ',' << stats[s] << ','
            << text::csv_number(c.stats[m][s]) << suffix << '\n';
  }
}

std::vector<CellResult> read_sweep_csv(const fs::path& path, const SweepSpec& spec) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot read file");
  const auto& stats = sweep_statistics();
  std::string line;
  if (!std::getline(in, line) || line != csv_header(spec))
    throw InputError(path.string() + ":1: header does not match the sweep of sweep.json");
  const std::size_t na = spec.axes.size();
  std::map<std::size_t, CellResult> cells;
  std::map<std::size_t, std::size_t> rows_of;
  std::vector<std::string> f;
  for (int line_no = 2; std::getline(in, line); ++line_no) {
    auto fail = [&](const std::string& why) -> InputError {
      return InputError(path.string() + ":" + std::to_string(line_no) + ": " + why);
    };
    if (line.empty()) continue;
    if (!split_csv(line, f) || f.size() != na + 8)
      throw fail("expected " + std::to_string(na + 8) + " fields");
    double cell_d = 0;
    if (!text::parse_number(f[0], cell_d) || cell_d < 0 || cell_d != std::floor(cell_d) ||
        cell_d >= double(spec.cell_count()))
      throw fail("bad cell index '" + f[0] + "'");
    const std::size_t cell = std::size_t(cell_d);
    const std::vector<std::size_t> coord = spec.cell_coordinates(cell);
    for (std::size_t a = 0; a < na; ++a)
      if (f[1 + a] != spec.axes[a].values[coord[a]])
        throw fail("value '" + f[1 + a] + "' of " + spec.axes[a].key + " is not cell " + f[0] +
                   "'s");
    const auto mi = std::find(spec.methods.begin(), spec.methods.end(), f[na + 1]);
    const auto si = std::find(stats.begin(), stats.end(), f[na + 2]);
    if (mi == spec.methods.end()) throw fail("unknown method '" + f[na + 1] + "'");
    if (si == stats.end()) throw fail("unknown statistic '" + f[na + 2] + "'");
    const std::string& v = f[na + 3];
    double value = 0;
    if (v == "nan")
      value = kNaN;
    else if (v == "inf")
      value = kInf;
    else if (v == "-inf")
      value = -kInf;
    else if (!text::parse_number(v, value))
      throw fail("bad value '" + v + "'");
    const std::string& status = f[na + 6];
    if (status != "ok" && status != "failed") throw fail("status must be ok or failed");
    auto [it, fresh] = cells.try_emplace(cell);
    CellResult& c = it->second;
    if (fresh) {
      c.cell = cell;
      c.seed = std::strtoull(f[na + 4].c_str(), nullptr, 10);
      c.failed = status == "failed";
      c.message = f[na + 7];
      c.stats.assign(spec.methods.size(), std::vector<double>(stats.size(), kNaN));
    }
    c.stats[std::size_t(mi - spec.methods.begin())][std::size_t(si - stats.begin())] = value;
    ++rows_of[cell];
  }
  std::vector<CellResult> out;
  for (auto& [cell, c] : cells) {
    if (rows_of[cell] != spec.methods.size() * stats.size())
      throw InputError(path.string() + ": cell " + std::to_string(cell) + " has " +
                       std::to_string(rows_of[cell]) + " rows, expected " +
                       std::to_string(spec.methods.size() * stats.size()));
    out.push_back(std::move(c));
  }
  return out;
}

// ---- HTML ----

namespace {

// Whether a method fails in a cell: 1 fails, 0 holds, -1 unknown.
int fail_state(const SweepSpec& spec, const CellResult* c, std::size_t method) {
  if (!c || c->failed) return -1;
  const auto& stats = sweep_statistics();
  const std::size_t s =
      std::size_t(std::find(stats.begin(), stats.end(), spec.fail_statistic) - stats.begin());
  const double v = c->stats[method][s];
  if (std::isnan(v)) return -1;
  return v > spec.fail_threshold_m ? 1 : 0;
}

std::string axis_values_text(const GridAxis& a) {
  std::string s;
  for (std::size_t i = 0; i < a.values.size(); ++i) s += (i ? ", " : "") + a.values[i];
  return s;
}

// One heat map panel: axis 0 across, axis 1 up (if any), the other axes
// fixed at `rest` (value indices of axes 2...).
void heat_map_svg(std::ostream& o, const SweepSpec& spec,
                  const std::map<std::size_t, const CellResult*>& by_cell, std::size_t method,
                  std::size_t stat, const Scale& scale, const std::vector<std::size_t>& rest) {
  const GridAxis& ax = spec.axes[0];
  const std::size_t nx = ax.values.size();
  const std::size_t ny = spec.axes.size() > 1 ? spec.axes[1].values.size() : 1;
  const double cw = std::clamp(440.0 / double(nx), 14.0, 56.0);
  const double ch = std::clamp(280.0 / double(ny), 14.0, 36.0);
  const double left = spec.axes.size() > 1 ? 62 : 8, bottom = 22, top = 4, right = 6;
  const double w = left + cw * double(nx) + right, h = top + ch * double(ny) + bottom;
  const StatisticUnit disp = statistic_unit(sweep_statistics()[stat]);

  // Cell index of (x, y).
  auto cell_at = [&](std::size_t x, std::size_t y) {
    std::vector<std::size_t> c{x};
    if (spec.axes.size() > 1) c.push_back(y);
    c.insert(c.end(), rest.begin(), rest.end());
    std::size_t idx = 0;
    for (std::size_t a = 0; a < spec.axes.size(); ++a)
      idx = idx * spec.axes[a].values.size() + c[a];
    return idx;
  };
  auto result_at = [&](std::size_t x, std::size_t y) -> const CellResult* {
    const auto it = by_cell.find(cell_at(x, y));
    return it == by_cell.end() ? nullptr : it->second;
  };
  auto px = [&](std::size_t x) { return left + cw * double(x); };
  // Row 0 (first value) at the bottom.
  auto py = [&](std::size_t y) { return top + ch * double(ny - 1 - y); };

  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h
    << "\" font-family=\"sans-serif\" font-size=\"9\">";
  for (std::size_t y = 0; y < ny; ++y) {
    for (std::size_t x = 0; x < nx; ++x) {
      const CellResult* c = result_at(x, y);
      const double X = px(x), Y = py(y);
      std::string tip = "cell " + std::to_string(cell_at(x, y));
      for (const std::string& ov : spec.cell_overrides(cell_at(x, y))) tip += "\n" + ov;
      if (!c) {
        o << "<rect x=\"" << X << "\" y=\"" << Y << "\" width=\"" << cw << "\" height=\"" << ch
          << "\" fill=\"#fff\" stroke=\"#ccc\" stroke-dasharray=\"2,2\"><title>"
          << text::html_escape(tip + "\nnot run in this part") << "</title></rect>";
        continue;
      }
      if (c->failed) {
        o << "<rect x=\"" << X << "\" y=\"" << Y << "\" width=\"" << cw << "\" height=\"" << ch
          << "\" fill=\"#bbb\" stroke=\"#fff\"><title>"
          << text::html_escape(tip + "\nFAILED: " + c->message) << "</title></rect>"
          << "<path d=\"M" << X + 3 << ' ' << Y + 3 << "L" << X + cw - 3 << ' ' << Y + ch - 3 << "M"
          << X + cw - 3 << ' ' << Y + 3 << "L" << X + 3 << ' ' << Y + ch - 3
          << "\" stroke=\"#666\" stroke-width=\"1.2\"/>";
        continue;
      }
      const double v = c->stats[method][stat];
      std::string fill = "#eee";
      double t = 0.5;
      if (std::isinf(v) && v > 0) {
        fill = "#111";
        t = 0;
      } else if (std::isfinite(v)) {
        t = scale.t(std::max(v, scale.log ? scale.lo : v));
        fill = colour(t);
      }
      const std::string shown = short_value(v * disp.scale);
      o << "<rect x=\"" << X << "\" y=\"" << Y << "\" width=\"" << cw << "\" height=\"" << ch
        << "\" fill=\"" << fill << "\" stroke=\"#fff\" stroke-width=\"0.5\"><title>"
        << text::html_escape(tip + "\n" + shown + " " + disp.shown) << "</title></rect>";
      if (cw >= 30 && ch >= 14)
        o << "<text x=\"" << X + cw / 2 << "\" y=\"" << Y + ch / 2 + 3
          << "\" text-anchor=\"middle\" fill=\"" << (fill == "#eee" || t > 0.6 ? "#000" : "#fff")
          << "\">" << text::html_escape(shown) << "</text>";
    }
  }
  // Cells where the method fails, outlined; the boundary between failing and
  // holding neighbours, drawn.
  for (std::size_t y = 0; y < ny; ++y)
    for (std::size_t x = 0; x < nx; ++x) {
      const int f = fail_state(spec, result_at(x, y), method);
      if (f == 1)
        o << "<rect x=\"" << px(x) + 1.5 << "\" y=\"" << py(y) + 1.5 << "\" width=\"" << cw - 3
          << "\" height=\"" << ch - 3 << "\" fill=\"none\" stroke=\"#e8112d\" stroke-width=\"2\"/>";
      if (f < 0) continue;
      if (x + 1 < nx) {
        const int g = fail_state(spec, result_at(x + 1, y), method);
        if (g >= 0 && g != f)
          o << "<line x1=\"" << px(x + 1) << "\" y1=\"" << py(y) << "\" x2=\"" << px(x + 1)
            << "\" y2=\"" << py(y) + ch << "\" stroke=\"#000\" stroke-width=\"3\"/>";
      }
      if (y + 1 < ny) {
        const int g = fail_state(spec, result_at(x, y + 1), method);
        if (g >= 0 && g != f)
          o << "<line x1=\"" << px(x) << "\" y1=\"" << py(y) << "\" x2=\"" << px(x) + cw
            << "\" y2=\"" << py(y) << "\" stroke=\"#000\" stroke-width=\"3\"/>";
      }
    }
  // Tick labels, thinned so they do not overlap.
  std::size_t longest = 1;
  for (const std::string& v : ax.values) longest = std::max(longest, v.size());
  const std::size_t every =
      std::max<std::size_t>(1, std::size_t(std::ceil(double(longest) * 5.5 / cw)));
  for (std::size_t x = 0; x < nx; x += every)
    o << "<text x=\"" << px(x) + cw / 2 << "\" y=\"" << top + ch * double(ny) + 12
      << "\" text-anchor=\"middle\">" << text::html_escape(ax.values[x]) << "</text>";
  if (spec.axes.size() > 1) {
    const std::size_t every_y = std::max<std::size_t>(1, std::size_t(std::ceil(11.0 / ch)));
    for (std::size_t y = 0; y < ny; y += every_y)
      o << "<text x=\"" << left - 4 << "\" y=\"" << py(y) + ch / 2 + 3 << "\" text-anchor=\"end\">"
        << text::html_escape(spec.axes[1].values[y]) << "</text>";
  }
  o << "</svg>";
}

void legend_svg(std::ostream& o, const Scale& scale, const StatisticUnit& disp) {
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"470\" height=\"30\" "
       "font-family=\"sans-serif\" font-size=\"10\">";
  for (int i = 0; i < 50; ++i)
    o << "<rect x=\"" << 60 + i * 5 << "\" y=\"2\" width=\"5.5\" height=\"12\" fill=\""
      << colour(i / 49.0) << "\"/>";
  if (scale.any) {
    o << "<text x=\"56\" y=\"12\" text-anchor=\"end\">" << (scale.log && scale.lo > 0 ? "&le;" : "")
      << short_value(scale.lo * disp.scale) << "</text><text x=\"314\" y=\"12\">"
      << short_value(scale.hi * disp.scale) << " " << disp.shown << (scale.log ? " (log)" : "")
      << "</text>";
  }
  o << "<text x=\"60\" y=\"26\">grey x: run failed; black: never converged; red outline: method "
       "fails</text></svg>";
}

}  // namespace

std::string sweep_html(const SweepSpec& spec, const std::vector<CellResult>& cells) {
  const auto& stats = sweep_statistics();
  std::map<std::size_t, const CellResult*> by_cell;
  for (const CellResult& c : cells) by_cell[c.cell] = &c;
  const std::size_t n_cells = spec.cell_count();
  std::size_t n_failed = 0;
  for (const CellResult& c : cells) n_failed += c.failed;

  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Sweep: "
    << text::html_escape(spec.scenario_name) << "</title>\n<style>"
    << "body{font-family:sans-serif;margin:1.5em;max-width:1400px}"
    << "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px "
       "6px;font-size:13px}"
    << ".maps{display:flex;flex-wrap:wrap;gap:18px;align-items:flex-start}.m{font-size:13px}"
    << ".fail{color:#c00}summary{font-weight:bold;cursor:pointer;margin-top:.6em}"
    << "</style></head><body>\n";
  o << "<h1>Sweep: " << text::html_escape(spec.scenario_name) << "</h1>\n<p>Scenario <code>"
    << text::html_escape(spec.scenario.string()) << "</code>";
  for (const std::string& ov : spec.overrides)
    o << " <code>--set " << text::html_escape(ov) << "</code>";
  o << "; " << spec.runs << " run(s) per cell, seeds from each cell's overrides and the scenario "
    << "seed " << spec.scenario_seed << ". " << cells.size() << " of " << n_cells
    << " cells in these results, " << n_failed << " failed to run.</p>\n<table><tr><th>axis</th>"
    << "<th>key</th><th>values</th></tr>";
  const char* axis_role[] = {"x (across)", "y (up)"};
  for (std::size_t a = 0; a < spec.axes.size(); ++a)
    o << "<tr><td>" << (a < 2 ? axis_role[a] : ("panel " + std::to_string(a - 1)).c_str())
      << "</td><td><code>" << text::html_escape(spec.axes[a].key) << "</code></td><td>"
      << text::html_escape(axis_values_text(spec.axes[a])) << "</td></tr>";
  const StatisticUnit fail_unit = statistic_unit(spec.fail_statistic);
  o << "</table>\n<p>A method <b>fails</b> in a cell where its <code>"
    << text::html_escape(spec.fail_statistic) << "</code> exceeds "
    << text::format_g(spec.fail_threshold_m * fail_unit.scale, 6) << " " << fail_unit.shown
    << " (<code>--fail-threshold-m " << text::format_g(spec.fail_threshold_m, 6) << "</code>, in "
    << fail_unit.si << ")"
    << ": outlined in red on every map of that method; a thick black line separates failing "
       "cells from holding neighbours.</p>\n";

  // Where each method breaks along the first axis.
  const GridAxis& a0 = spec.axes[0];
  std::size_t rows = n_cells / a0.values.size();
  o << "<h2>Where each method breaks</h2>\n<table><tr><th>";
  for (std::size_t a = 1; a < spec.axes.size(); ++a)
    o << (a > 1 ? ", " : "") << "<code>" << text::html_escape(spec.axes[a].key) << "</code>";
  if (spec.axes.size() == 1) o << "&nbsp;";
  o << "</th>";
  for (const std::string& m : spec.methods) o << "<th>" << text::html_escape(m) << "</th>";
  o << "</tr>\n";
  for (std::size_t r = 0; r < rows; ++r) {
    // Cells of this row: axis 0 varies slowest, so stride `rows`.
    const std::vector<std::size_t> coord = spec.cell_coordinates(r);
    o << "<tr><td>";
    for (std::size_t a = 1; a < spec.axes.size(); ++a)
      o << (a > 1 ? ", " : "") << text::html_escape(spec.axes[a].values[coord[a]]);
    if (spec.axes.size() == 1) o << "all";
    o << "</td>";
    for (std::size_t m = 0; m < spec.methods.size(); ++m) {
      std::vector<int> f;
      for (std::size_t x = 0; x < a0.values.size(); ++x) {
        const auto it = by_cell.find(x * rows + r);
        f.push_back(fail_state(spec, it == by_cell.end() ? nullptr : it->second, m));
      }
      std::vector<std::size_t> failing;
      bool unknown = false;
      for (std::size_t x = 0; x < f.size(); ++x) {
        if (f[x] == 1) failing.push_back(x);
        if (f[x] < 0) unknown = true;
      }
      std::string text;
      if (failing.empty()) {
        text = unknown ? "holds where known" : "holds";
      } else if (failing.size() == f.size()) {
        text = "fails everywhere";
      } else if (failing.back() == f.size() - 1 && failing.size() == f.size() - failing.front()) {
        text = "fails from " + a0.key + " = " + a0.values[failing.front()];
      } else {
        text = "fails at " + a0.key + " = ";
        for (std::size_t i = 0; i < failing.size(); ++i)
          text += (i ? ", " : "") + a0.values[failing[i]];
      }
      o << "<td" << (failing.empty() ? "" : " class=\"fail\"") << ">" << text::html_escape(text)
        << "</td>";
    }
    o << "</tr>\n";
  }
  o << "</table>\n";

  if (n_failed) {
    o << "<h2>Cells that failed to run</h2>\n<table><tr><th>cell</th><th>overrides</th>"
         "<th>message</th></tr>\n";
    for (const CellResult& c : cells) {
      if (!c.failed) continue;
      std::string ov;
      for (const std::string& s : spec.cell_overrides(c.cell)) ov += (ov.empty() ? "" : " ") + s;
      o << "<tr><td>" << c.cell << "</td><td><code>" << text::html_escape(ov) << "</code></td><td>"
        << text::html_escape(c.message) << "</td></tr>\n";
    }
    o << "</table>\n";
  }

  // Panels: every combination of the axes after the first two.
  std::size_t panels = 1;
  for (std::size_t a = 2; a < spec.axes.size(); ++a) panels *= spec.axes[a].values.size();
  o << "<h2>Heat maps</h2>\n<p>Across: <code>" << text::html_escape(a0.key) << "</code>";
  if (spec.axes.size() > 1) o << "; up: <code>" << text::html_escape(spec.axes[1].key) << "</code>";
  if (panels > 1) o << "; one small map per value of the other axes";
  o << ". Hover a cell for its overrides and value.</p>\n";
  const std::set<std::string> open = {"p50_translation_m", "converged_p50_translation_m",
                                      "converged_p99_translation_m", "convergence_time_s"};
  for (std::size_t s = 0; s < stats.size(); ++s) {
    const StatisticUnit disp = statistic_unit(stats[s]);
    Scale scale;
    double lo = kInf, hi = -kInf;
    for (const CellResult& c : cells)
      if (!c.failed)
        for (std::size_t m = 0; m < spec.methods.size(); ++m) {
          const double v = c.stats[m][s];
          if (!std::isfinite(v)) continue;
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
    if (lo <= hi) {
      scale.any = true;
      scale.lo = lo;
      scale.hi = hi;
      // Logarithmic for errors spanning more than a decade, over at most
      // three decades (a numerically zero error would squash the rest).
      scale.log = stats[s] != "convergence_time_s" && hi > 0 && hi > 10 * lo;
      if (scale.log) scale.lo = std::max(lo, hi * 1e-3);
    }
    o << "<details" << (open.count(stats[s]) ? " open" : "") << "><summary>" << stats[s] << " ("
      << "shown in " << disp.shown << ")</summary>\n";
    legend_svg(o, scale, disp);
    o << "\n";
    for (std::size_t m = 0; m < spec.methods.size(); ++m) {
      o << "<div class=\"m\"><b>" << text::html_escape(spec.methods[m])
        << "</b></div><div class=\"maps\">";
      for (std::size_t p = 0; p < panels; ++p) {
        std::vector<std::size_t> rest(spec.axes.size() > 2 ? spec.axes.size() - 2 : 0);
        std::size_t q = p;
        for (std::size_t a = spec.axes.size(); a-- > 2;) {
          rest[a - 2] = q % spec.axes[a].values.size();
          q /= spec.axes[a].values.size();
        }
        o << "<div>";
        if (panels > 1) {
          o << "<div class=\"m\">";
          for (std::size_t a = 2; a < spec.axes.size(); ++a)
            o << (a > 2 ? ", " : "") << text::html_escape(spec.axes[a].key) << " = "
              << text::html_escape(spec.axes[a].values[rest[a - 2]]);
          o << "</div>";
        }
        heat_map_svg(o, spec, by_cell, m, s, scale, rest);
        o << "</div>";
      }
      o << "</div>\n";
    }
    o << "</details>\n";
  }
  o << "</body></html>\n";
  return o.str();
}

// ---- manifest, outputs, merge ----

namespace {

Json spec_json(const SweepSpec& spec) {
  Json axes = Json::array();
  for (const GridAxis& a : spec.axes)
    axes.push_back(Json{{"spec", a.spec}, {"key", a.key}, {"values", a.values}});
  return Json{{"scenario", spec.scenario.string()},
              {"scenario_name", spec.scenario_name},
              {"scenario_seed", spec.scenario_seed},
              {"overrides", spec.overrides},
              {"grid", axes},
              {"methods", spec.methods},
              {"runs", spec.runs},
              {"fail_statistic", spec.fail_statistic},
              {"fail_threshold_m", spec.fail_threshold_m},
              {"cells", spec.cell_count()}};
}

SweepSpec spec_from_json(const Json& j) {
  SweepSpec s;
  s.scenario = j.at("scenario").get<std::string>();
  s.scenario_name = j.at("scenario_name").get<std::string>();
  s.scenario_seed = j.at("scenario_seed").get<std::uint64_t>();
  s.overrides = j.at("overrides").get<std::vector<std::string>>();
  for (const Json& a : j.at("grid"))
    s.axes.push_back({a.at("spec").get<std::string>(), a.at("key").get<std::string>(),
                      a.at("values").get<std::vector<std::string>>()});
  s.methods = j.at("methods").get<std::vector<std::string>>();
  s.runs = j.at("runs").get<int>();
  s.fail_statistic = j.at("fail_statistic").get<std::string>();
  s.fail_threshold_m = j.at("fail_threshold_m").get<double>();
  if (s.axes.empty() || s.methods.empty()) throw std::runtime_error("no grid or no methods");
  for (const GridAxis& a : s.axes)
    if (a.values.empty()) throw std::runtime_error("an axis without values");
  return s;
}

}  // namespace

std::string sweep_manifest_json(const SweepSpec& spec, const Shard& shard,
                                const std::vector<CellResult>& cells) {
  std::vector<std::size_t> run;
  for (const CellResult& c : cells) run.push_back(c.cell);
  const Json j{{"sweep", spec_json(spec)},
               {"shard", {{"index", shard.index}, {"count", shard.count}}},
               {"cells_run", run}};
  return j.dump(2) + "\n";
}

void write_sweep_outputs(const fs::path& dir, const SweepSpec& spec, const Shard& shard,
                         std::vector<CellResult> cells) {
  std::sort(cells.begin(), cells.end(),
            [](const CellResult& a, const CellResult& b) { return a.cell < b.cell; });
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create folder: " + ec.message());
  std::ostringstream csv;
  write_sweep_csv(csv, spec, cells);
  text::write_text(dir / "sweep.csv", csv.str());
  text::write_text(dir / "sweep.html", sweep_html(spec, cells));
  text::write_text(dir / "sweep.json", sweep_manifest_json(spec, shard, cells));
}

void merge_sweep_parts(const std::vector<fs::path>& parts, const fs::path& out) {
  if (parts.empty()) throw InputError("merge: name at least one part folder");
  std::optional<SweepSpec> spec;
  std::string spec_text;
  fs::path first;
  std::map<std::size_t, fs::path> seen;
  std::vector<CellResult> cells;
  for (const fs::path& dir : parts) {
    const fs::path manifest = dir / "sweep.json";
    std::ifstream in(manifest);
    if (!in)
      throw InputError(manifest.string() + ": cannot read file (is " + dir.string() +
                       " the --out folder of an arttrack sweep?)");
    Json j;
    SweepSpec s;
    try {
      j = Json::parse(in);
      s = spec_from_json(j.at("sweep"));
    } catch (const std::exception& e) {
      throw InputError(manifest.string() + ": not a sweep manifest: " + e.what());
    }
    const std::string text = j.at("sweep").dump();
    if (!spec) {
      spec = s;
      spec_text = text;
      first = dir;
    } else if (text != spec_text) {
      throw InputError("merge: " + dir.string() + " holds another sweep than " + first.string() +
                       " (scenario, overrides, grid, methods, runs or failure criterion differ)");
    }
    for (CellResult& c : read_sweep_csv(dir / "sweep.csv", s)) {
      const auto [it, fresh] = seen.emplace(c.cell, dir);
      if (!fresh)
        throw InputError("merge: cell " + std::to_string(c.cell) + " is in both " +
                         it->second.string() + " and " + dir.string());
      cells.push_back(std::move(c));
    }
  }
  std::vector<std::size_t> missing;
  for (std::size_t c = 0; c < spec->cell_count(); ++c)
    if (!seen.count(c)) missing.push_back(c);
  if (!missing.empty()) {
    std::string list;
    for (std::size_t i = 0; i < missing.size() && i < 10; ++i)
      list += (i ? ", " : "") + std::to_string(missing[i]);
    if (missing.size() > 10) list += ", ...";
    throw InputError("merge: " + std::to_string(missing.size()) + " of " +
                     std::to_string(spec->cell_count()) + " cells are in no part (cells " + list +
                     "): is a shard missing or unfinished?");
  }
  write_sweep_outputs(out, *spec, Shard{}, std::move(cells));
}

}  // namespace arttrack::sim
