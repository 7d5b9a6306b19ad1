// A sweep's files: sweep.csv (written and read back), sweep.json (the
// manifest merge checks), writing a sweep's outputs and merging shards.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "arttrack/sim/internal/text_format.h"
#include "arttrack/sim/sweep.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/non_finite.h"

namespace arttrack::sim {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// ---- CSV ----

namespace {

std::vector<std::string> csv_header(const SweepSpec& spec) {
  std::vector<std::string> h = {"cell"};
  for (const GridAxis& a : spec.axes) h.push_back(a.key);
  for (const char* c : {"method", "statistic", "value", "seed", "runs", "status", "message"})
    h.push_back(c);
  return h;
}

}  // namespace

void write_sweep_csv(std::ostream& out, const SweepSpec& spec,
                     const std::vector<CellResult>& cells) {
  const auto& stats = sweep_statistics();
  const std::vector<std::string> header = csv_header(spec);
  for (std::size_t i = 0; i < header.size(); ++i)
    out << (i ? "," : "") << text::csv_field(header[i]);
  out << '\n';
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
  // Written by write_sweep_csv: every field as it was written.
  text::CsvReader csv(path, text::CsvSpace::kVerbatim);
  const auto& stats = sweep_statistics();
  std::vector<std::string> f;
  if (!csv.next(f) || f != csv_header(spec))
    csv.fail("header does not match the sweep of sweep.json");
  const std::size_t na = spec.axes.size();
  std::map<std::size_t, CellResult> cells;
  std::map<std::size_t, std::size_t> rows_of;
  while (csv.next(f)) {
    auto fail = [&](const std::string& why) -> InputError {
      return InputError(csv.where() + ": " + why);
    };
    if (f.size() != na + 8) throw fail("expected " + std::to_string(na + 8) + " fields");
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
    if (!text::parse_number_or_non_finite(v, value)) throw fail("bad value '" + v + "'");
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
