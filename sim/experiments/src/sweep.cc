#include "arttrack/sim/sweep.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>

#include "arttrack/sim/internal/text_format.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/non_finite.h"
#include "arttrack/tracker/units.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxAxisValues = 10000;

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
  if (statistic.find("rotation") != std::string::npos) return {"rad", "deg", kDegPerRad};
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

}  // namespace arttrack::sim
