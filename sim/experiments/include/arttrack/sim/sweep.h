// Stress sweeps: one scenario run over a Cartesian grid of scenario keys
// (`arttrack sweep`), every tracking method in every cell, K seeds per cell,
// summarised per (cell, method, statistic) in sweep.csv and as heat maps in
// sweep.html, with the cells where a method breaks outlined.
//
// Grid keys are scenario keys as `arttrack run --set` takes them, plus list
// elements: `encoders[0].offset_deg`, `occluders[1].sweep.passes`.
//
// Cells are numbered in row-major order of the axes (the last axis varies
// fastest). A cell's seed is a hash of its overrides and the scenario seed,
// never of the shard that runs it, so `--shard I/N` parts merge into exactly
// the outputs of one unsharded run (merge_sweep_parts).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"

namespace arttrack::sim {

// ---- statistics by name (shared with tuning) ----

// Statistic names of a method's result, in sweep.csv order:
// `{p1,p25,p50,p75,p99}_translation_m`, `..._rotation_rad` (all samples),
// `converged_{p1,...,p99}_translation_m`, `converged_..._rotation_rad`
// (samples at time >= converged_after_s) and `convergence_time_s` (median
// over runs, +inf if half the runs or more never converge).
const std::vector<std::string>& sweep_statistics();

// A statistic of `method` by name: any of sweep_statistics(), or
// `p50_image_update_ms` / `p99_image_update_ms` (wall time: not
// reproducible). Unknown name: InputError naming it and the known ones.
double method_statistic(const MethodResult& method, const std::string& name);

// Checks a statistic name (as method_statistic); `context` names the option.
void check_statistic_name(const std::string& name, const std::string& context);

// The units of a statistic: `si` the one it is stored and compared in (m,
// rad or s: also that of --fail-threshold-m for it), `shown` the one tables
// and pages show (mm, deg or s), value_shown = value * scale.
struct StatisticUnit {
  std::string si;
  std::string shown;
  double scale = 1;
};
StatisticUnit statistic_unit(const std::string& statistic);

// ---- the grid ----

// One axis of the grid: a scenario key and the values it takes.
struct GridAxis {
  std::string spec;                 // as given, named in messages
  std::string key;                  // e.g. camera.latency_s, encoders[0].offset_deg
  std::vector<std::string> values;  // each value's YAML text
};

// Parses `key=start:stop:step` (start, start + step, ... up to stop
// inclusive, within a millionth of a step; step > 0, stop >= start, at most
// 10000 values) or `key=v1,v2,...` (YAML values without commas). Errors:
// InputError naming the spec and what is wrong.
GridAxis parse_grid_axis(const std::string& spec);

// Which cells a process runs: those with index % count == index.
struct Shard {
  int index = 0;
  int count = 1;
  bool contains(std::size_t cell) const { return int(cell % std::size_t(count)) == index; }
};
// Parses "I/N" (0 <= I < N); InputError naming the text otherwise.
Shard parse_shard(const std::string& text);

// Everything that defines a sweep's results (not who runs which cells).
struct SweepSpec {
  std::filesystem::path scenario;
  // Fixed overrides (--set), applied before the grid's.
  std::vector<std::string> overrides;
  std::vector<GridAxis> axes;
  // Methods (empty before resolve_sweep: the scenario's).
  std::vector<std::string> methods;
  // Runs per cell (0 before resolve_sweep: the scenario's).
  int runs = 0;
  // The scenario seed the cells' seeds derive from (--seed); -1: the
  // scenario's `seed`.
  long long seed = -1;
  // A method fails in a cell where this statistic exceeds the threshold, in
  // the statistic's SI unit (metres for the translation statistics).
  double fail_threshold_m = 0.05;
  std::string fail_statistic = "converged_p50_translation_m";
  // Filled by resolve_sweep: the scenario's name, and `seed` if set, else
  // the scenario's seed (after overrides).
  std::string scenario_name;
  std::uint64_t scenario_seed = 0;

  std::size_t cell_count() const;
  // Value index per axis of a cell.
  std::vector<std::size_t> cell_coordinates(std::size_t cell) const;
  // The cell's grid overrides, `key=value` per axis, in axis order.
  std::vector<std::string> cell_overrides(std::size_t cell) const;
};

// Checks a sweep and fills its methods, runs, scenario name and seed from
// the scenario (the seed from `seed` when that is >= 0): the scenario must load with the fixed
// overrides, every axis key must be one the scenario accepts (an unknown key or a path through a
// non-map is an InputError naming the axis spec), methods must be known.
// Values a key rejects are not errors here: their cells fail when run.
void resolve_sweep(SweepSpec& spec);

// The seed of a cell: a SplitMix64 mix of a 64-bit FNV-1a hash of its
// overrides (joined by newlines) and the scenario seed, cut to 53 bits.
std::uint64_t cell_seed(const std::vector<std::string>& cell_overrides,
                        std::uint64_t scenario_seed);

// ---- running ----

// One cell's outcome.
struct CellResult {
  std::size_t cell = 0;
  std::uint64_t seed = 0;
  // Failed: the scenario rejected a value or a run threw; `message` says why
  // (one line) and every statistic is NaN.
  bool failed = false;
  std::string message;
  // [method][statistic], SweepSpec::methods and sweep_statistics() order.
  std::vector<std::vector<double>> stats;
};

// Runs one cell of a resolved sweep (never throws for the cell's own
// failures: they are recorded). `progress` may be empty.
CellResult run_sweep_cell(const SweepSpec& spec, std::size_t cell,
                          const std::function<void(const RunProgress&)>& progress = {});

// ---- outputs ----

// sweep.csv: header `cell,<axis keys>,method,statistic,value,seed,runs,status,message`,
// then per cell (ascending) x method x statistic one row; values `%.17g`
// (exact round trip), `nan`/`inf`; status `ok` or `failed`.
void write_sweep_csv(std::ostream& out, const SweepSpec& spec,
                     const std::vector<CellResult>& cells);
// Reads what write_sweep_csv wrote for the same spec; InputError naming the
// file and line otherwise.
std::vector<CellResult> read_sweep_csv(const std::filesystem::path& path, const SweepSpec& spec);

// sweep.html: self-contained (inline SVG, no script): per statistic and
// method a heat map over the first two axes (small multiples over the
// others), cells where the method fails outlined and the failure boundary
// drawn, a table of where each method breaks along the first axis, and the
// failed cells with their messages. Cells absent from `cells` (other
// shards) are drawn empty.
std::string sweep_html(const SweepSpec& spec, const std::vector<CellResult>& cells);

// sweep.json: the spec, the shard and the cells run (what merge checks).
std::string sweep_manifest_json(const SweepSpec& spec, const Shard& shard,
                                const std::vector<CellResult>& cells);

// Writes DIR/sweep.csv, DIR/sweep.html and DIR/sweep.json (DIR created).
// Cannot write: InputError naming the path.
void write_sweep_outputs(const std::filesystem::path& dir, const SweepSpec& spec,
                         const Shard& shard, std::vector<CellResult> cells);

// Combines the outputs of shard runs (each DIR holds sweep.json and
// sweep.csv) into `out`: exactly what one unsharded run writes. Parts of
// different sweeps, cells run twice or cells missing: InputError naming them.
void merge_sweep_parts(const std::vector<std::filesystem::path>& parts,
                       const std::filesystem::path& out);

}  // namespace arttrack::sim
