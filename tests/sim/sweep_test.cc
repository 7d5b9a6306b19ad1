// Stress sweeps on the small dual-arm robot of the scenario tests (160x120
// camera, 1.5 simulated seconds, 1 run):
//   - grid specifications: ranges include their end, lists keep their text,
//     and bad ones (stop below start, non-numbers, zero step, unknown keys,
//     indices past the end) are errors naming the spec;
//   - list elements can be swept (encoders[0].offset_deg reaches the
//     scenario's encoder group);
//   - a cell's seed depends on its overrides and the scenario seed only;
//   - sharded runs merged give exactly the bytes of one unsharded run, with
//     failed cells (a value the scenario rejects) reported and the others run;
//   - the same through the arttrack program and GNU parallel (tools/setup.sh
//     installs it; skipped where it is missing).
#include "arttrack/sim/sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "../error_of.h"
#include "../text_search.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/units.h"
#include "scenario_test_robot.h"

namespace arttrack::sim {
namespace {

using test_support::count_occurrences;

using arttrack::test_support::error_of;

namespace fs = std::filesystem;

const std::string kSweepScenario =
    test::short_scenario(5, "[encoders_only, full_fusion]", "particle_filter.particles: 8, ");

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SweepGrid, RangesIncludeTheirEndAndListsKeepTheirText) {
  const GridAxis a = parse_grid_axis("camera.latency_s=0:0.1:0.025");
  EXPECT_EQ(a.key, "camera.latency_s");
  EXPECT_EQ(a.values, (std::vector<std::string>{"0", "0.025", "0.05", "0.075", "0.1"}));
  // 0.1 + 0.2 is 0.30000000000000004 in binary: the text stays 0.3.
  EXPECT_EQ(parse_grid_axis("k=0.1:0.3:0.1").values,
            (std::vector<std::string>{"0.1", "0.2", "0.3"}));
  // The end is included only when reached.
  EXPECT_EQ(parse_grid_axis("k=0:1:0.4").values, (std::vector<std::string>{"0", "0.4", "0.8"}));
  EXPECT_EQ(parse_grid_axis("k=-2:-1:1").values, (std::vector<std::string>{"-2", "-1"}));
  const GridAxis l = parse_grid_axis("camera.jitter=gaussian, uniform");
  EXPECT_EQ(l.values, (std::vector<std::string>{"gaussian", "uniform"}));
  EXPECT_EQ(parse_grid_axis("encoders[0].offset_deg=1,2").key, "encoders[0].offset_deg");
}

TEST(SweepGrid, BadSpecificationsAreErrorsNamingTheSpec) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"key=1:0:0.1", "stop 0 is below start 1"},
      {"key=a:b:c", "start 'a' is not a finite number"},
      {"key=0:1:0", "step must be > 0"},
      {"key=0:1:-0.5", "step must be > 0"},
      {"key=0:1", "three numbers"},
      {"key=0:1e9:1", "more than 10000"},
      {"key", "expected key=start:stop:step"},
      {"=1,2", "expected key=start:stop:step"},
      {"key=", "no values"},
      {"key=1,,2", "an empty value"},
      {"key=1,1", "listed twice"},
      {"a..b=1", "empty component"},
      {"a[x].b=1", "bad index"},
  };
  for (const auto& [spec, problem] : cases) {
    const std::string msg = error_of([&] { parse_grid_axis(spec); });
    EXPECT_NE(msg.find("--grid '" + spec + "'"), std::string::npos) << msg;
    EXPECT_NE(msg.find(problem), std::string::npos) << spec << ": " << msg;
  }
}

TEST(SweepGrid, ShardsAreValidated) {
  const Shard s = parse_shard("2/4");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 4);
  EXPECT_TRUE(s.contains(6));
  EXPECT_FALSE(s.contains(7));
  for (const char* bad : {"4/4", "-1/4", "1/0", "1", "a/b", "1.5/4"})
    EXPECT_NE(error_of([&] { parse_shard(bad); }).find(std::string("--shard '") + bad + "'"),
              std::string::npos)
        << bad;
}

TEST(SweepGrid, UnknownKeysAndBadIndicesAreErrorsNamingTheSpec) {
  const test::TestDir dir("sweep_keys");
  const fs::path scenario = dir.write("s.yaml", kSweepScenario);
  auto resolve = [&](const std::string& spec) {
    return error_of([&] {
      SweepSpec s;
      s.scenario = scenario;
      s.axes = {parse_grid_axis(spec)};
      resolve_sweep(s);
    });
  };
  std::string msg = resolve("camera.latncy_s=0:0.1:0.05");
  EXPECT_NE(msg.find("--grid 'camera.latncy_s=0:0.1:0.05'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("camera.latncy_s' is not a known key"), std::string::npos) << msg;
  msg = resolve("encoders[2].offset_deg=1,2");
  EXPECT_NE(msg.find("--grid 'encoders[2].offset_deg=1,2'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("has 1 element(s): no [2]"), std::string::npos) << msg;
  msg = resolve("encoders.offset_deg=1,2");
  EXPECT_NE(msg.find("'encoders' is not a map"), std::string::npos) << msg;
  // A value the scenario rejects is not a spec error: that cell fails.
  EXPECT_EQ(resolve("camera.drop_probability=0,1"), "");
}

TEST(SweepGrid, ListElementsCanBeSwept) {
  const test::TestDir dir("sweep_index");
  const fs::path scenario = dir.write("s.yaml", kSweepScenario);
  const Scenario s = load_scenario(
      scenario, {"encoders[0].offset_deg=2.5", "occluders=[]", "camera.latency_s=0.01"});
  ASSERT_EQ(s.encoders.groups.size(), 1u);
  EXPECT_NEAR(s.encoders.groups[0].offset_rad, 2.5 * kRadPerDeg, 1e-12);
  EXPECT_EQ(s.encoders.groups[0].joints.size(), 4u);  // the rest of the group stays
  EXPECT_DOUBLE_EQ(s.camera_timing.latency_s, 0.01);
  // A new key inside an element reaches it too, and overrides of one list add up.
  const Scenario t = load_scenario(
      scenario, {"encoders[0].noise_deg=0.5", "duration_s=2", "encoders[0].step_amplitude_deg=1"});
  EXPECT_NEAR(t.encoders.groups[0].noise_sigma_rad, 0.5 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(t.encoders.groups[0].step_amplitude_rad, 1 * kRadPerDeg, 1e-12);
  EXPECT_NEAR(t.encoders.groups[0].offset_rad, 5 * kRadPerDeg, 1e-12);
  EXPECT_EQ(t.duration_s, 2);
}

TEST(SweepGrid, CellsAndSeeds) {
  SweepSpec spec;
  spec.axes = {parse_grid_axis("a=1,2,3"), parse_grid_axis("b=x,y")};
  ASSERT_EQ(spec.cell_count(), 6u);
  // Row-major: the last axis fastest.
  EXPECT_EQ(spec.cell_coordinates(3), (std::vector<std::size_t>{1, 1}));
  EXPECT_EQ(spec.cell_overrides(4), (std::vector<std::string>{"a=3", "b=x"}));
  // Seeds: a function of the overrides and the scenario seed, 53 bits.
  std::set<std::uint64_t> seeds;
  for (std::size_t c = 0; c < 6; ++c) {
    const std::uint64_t s = cell_seed(spec.cell_overrides(c), 7);
    EXPECT_EQ(s, cell_seed(spec.cell_overrides(c), 7));
    EXPECT_LT(s, std::uint64_t(1) << 53);
    seeds.insert(s);
  }
  EXPECT_EQ(seeds.size(), 6u);
  EXPECT_NE(cell_seed({"a=1", "b=x"}, 7), cell_seed({"a=1", "b=x"}, 8));
  EXPECT_NE(cell_seed({"a=1", "b=x"}, 7), cell_seed({"a=1b=x"}, 7));
}

// The sweep of the sharding tests: 2 x 2 cells, 2 methods, 1 run; the cells
// with drop_probability 1 (cells 2 and 3) fail: the scenario rejects it.
// Each of two shards gets one cell that runs and one that fails.
SweepSpec small_sweep(const fs::path& scenario) {
  SweepSpec spec;
  spec.scenario = scenario;
  spec.axes = {parse_grid_axis("camera.drop_probability=0,1"),
               parse_grid_axis("camera.latency_s=0,0.03")};
  resolve_sweep(spec);
  return spec;
}

TEST(Sweep, ShardedAndUnshardedGiveIdenticalOutputs) {
  const test::TestDir dir("sweep_shards");
  const SweepSpec spec = small_sweep(dir.write("s.yaml", kSweepScenario));
  EXPECT_EQ(spec.methods, (std::vector<std::string>{"encoders_only", "full_fusion"}));
  EXPECT_EQ(spec.runs, 1);
  EXPECT_EQ(spec.scenario_seed, 5u);

  std::vector<CellResult> all;
  for (std::size_t c = 0; c < spec.cell_count(); ++c) all.push_back(run_sweep_cell(spec, c));
  write_sweep_outputs(dir.path() / "all", spec, Shard{}, all);

  // Failed cells carry the scenario's message; the others real numbers.
  for (const CellResult& r : all) {
    const bool should_fail = r.cell >= 2;
    EXPECT_EQ(r.failed, should_fail) << r.cell << ": " << r.message;
    if (should_fail) {
      EXPECT_NE(r.message.find("drop_probability"), std::string::npos) << r.message;
      EXPECT_TRUE(std::isnan(r.stats[0][0]));
    } else {
      ASSERT_EQ(r.stats.size(), 2u);
      for (const auto& m : r.stats)
        for (std::size_t s = 0; s + 1 < m.size(); ++s) EXPECT_TRUE(std::isfinite(m[s])) << s;
      // Encoders only sees the 5 degree bias; percentiles are ordered.
      EXPECT_GT(r.stats[0][2], 0.01);
      EXPECT_LE(r.stats[0][0], r.stats[0][4]);
    }
  }

  // Shards in reverse order, each from its own cells.
  for (int i : {1, 0}) {
    const Shard shard{i, 2};
    std::vector<CellResult> part;
    for (std::size_t c = 0; c < spec.cell_count(); ++c)
      if (shard.contains(c)) part.push_back(run_sweep_cell(spec, c));
    write_sweep_outputs(dir.path() / ("part" + std::to_string(i)), spec, shard, part);
  }
  merge_sweep_parts({dir.path() / "part1", dir.path() / "part0"}, dir.path() / "merged");
  for (const char* f : {"sweep.csv", "sweep.html", "sweep.json"})
    EXPECT_EQ(read_file(dir.path() / "all" / f), read_file(dir.path() / "merged" / f)) << f;

  // The CSV: one row per cell x method x statistic, failures marked.
  const std::string csv = read_file(dir.path() / "all" / "sweep.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "cell,camera.drop_probability,camera.latency_s,method,statistic,value,seed,runs,"
            "status,message");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 4 * 2 * 21);
  EXPECT_NE(csv.find("\n3,1,0.03,encoders_only,p1_translation_m,nan,"), std::string::npos);
  const std::vector<CellResult> back = read_sweep_csv(dir.path() / "all" / "sweep.csv", spec);
  ASSERT_EQ(back.size(), 4u);
  EXPECT_EQ(back[1].stats[1][3], all[1].stats[1][3]);  // exact round trip
  EXPECT_EQ(back[2].message, all[2].message);
  const std::string html = read_file(dir.path() / "all" / "sweep.html");
  EXPECT_NE(html.find("Where each method breaks"), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);

  // A missing part, a part twice and another sweep are errors naming them.
  std::string msg = error_of([&] { merge_sweep_parts({dir.path() / "part0"}, dir.path() / "m2"); });
  EXPECT_NE(msg.find("2 of 4 cells are in no part (cells 1, 3)"), std::string::npos) << msg;
  msg = error_of([&] {
    merge_sweep_parts({dir.path() / "part0", dir.path() / "all"}, dir.path() / "m3");
  });
  EXPECT_NE(msg.find("cell 0 is in both"), std::string::npos) << msg;
  SweepSpec other = spec;
  other.runs = 2;
  write_sweep_outputs(dir.path() / "other", other, Shard{1, 2}, {});
  msg = error_of([&] {
    merge_sweep_parts({dir.path() / "part0", dir.path() / "other"}, dir.path() / "m4");
  });
  EXPECT_NE(msg.find("holds another sweep"), std::string::npos) << msg;
}

// The <svg> element of `html` whose data-chart is `id` ("" if none).
std::string svg_of(const std::string& html, const std::string& id) {
  const std::size_t at = html.find("data-chart=\"" + id + "\"");
  if (at == std::string::npos) return "";
  const std::size_t begin = html.rfind("<svg", at);
  return html.substr(begin, html.find("</svg>", at) + 6 - begin);
}

// A 3 x 2 sweep's results made by hand (no simulation): 4 mm everywhere,
// except encoders_only's 20 mm per degree of encoders[0].offset_deg (fails
// above 50 mm from 5 degrees); cell 4 failed to run, cell 5 is in another
// shard.
std::vector<CellResult> hand_made_cells(const SweepSpec& spec) {
  const std::size_t n = sweep_statistics().size();
  std::vector<CellResult> cells;
  for (std::size_t c = 0; c < 5; ++c) {
    CellResult r;
    r.cell = c;
    r.stats.assign(spec.methods.size(), std::vector<double>(n, 0.004));
    const double offset_deg = std::stod(spec.axes[0].values[spec.cell_coordinates(c)[0]]);
    if (offset_deg > 0) std::fill(r.stats[0].begin(), r.stats[0].end(), 0.02 * offset_deg);
    if (c == 4) {
      r.failed = true;
      r.message = "value <rejected>";
      for (auto& m : r.stats) std::fill(m.begin(), m.end(), std::nan(""));
    }
    cells.push_back(r);
  }
  return cells;
}

TEST(SweepPage, HeatMapsNameTheirAxesAndMarkWhereAMethodFails) {
  SweepSpec spec;
  spec.scenario = "s.yaml";
  spec.scenario_name = "s";
  spec.axes = {parse_grid_axis("encoders[0].offset_deg=0,5,10"),
               parse_grid_axis("camera.latency_s=0,0.05")};
  spec.methods = {"encoders_only", "full_fusion"};
  spec.runs = 1;
  const std::string html = sweep_html(spec, hand_made_cells(spec));
  EXPECT_NE(html.find("fails at encoders[0].offset_deg = 5</td>"), std::string::npos);
  EXPECT_NE(html.find(">holds where known</td>"), std::string::npos);
  EXPECT_NE(html.find("value &lt;rejected&gt;"), std::string::npos);
  EXPECT_EQ(html.find("<rejected>"), std::string::npos);
  EXPECT_EQ(html.find("No cell has a value"), std::string::npos);

  const std::string map = svg_of(html, "converged_p50_translation_m-encoders_only-0");
  ASSERT_NE(map, "");
  // Both axes named by their keys, every value a tick; cell values in the
  // 12 px class; the two failing cells outlined and the boundary drawn.
  EXPECT_NE(map.find(">encoders[0].offset_deg</text>"), std::string::npos);
  EXPECT_NE(map.find(">camera.latency_s</text>"), std::string::npos);
  for (const char* v : {">0</text>", ">5</text>", ">10</text>", ">0.05</text>"})
    EXPECT_NE(map.find(v), std::string::npos) << v;
  EXPECT_EQ(count_occurrences(map, "class=\"hv\""), 4u);  // 4 cells with values: 4, 4, 100, 100 mm
  EXPECT_EQ(count_occurrences(map, ">100</text>"), 2u);
  EXPECT_EQ(count_occurrences(map, "stroke=\"#ff00ff\""), 2u);
  EXPECT_EQ(count_occurrences(map, "stroke=\"#000\" stroke-width=\"3\""), 2u);
  EXPECT_NE(map.find("FAILED: value &lt;rejected&gt;"), std::string::npos);
  EXPECT_NE(map.find("not run in this part"), std::string::npos);
  EXPECT_EQ(map.find("nan"), std::string::npos);
  // One colour scale per statistic, with its unit; the key to the cells.
  const std::string bar = svg_of(html, "colours-converged_p50_translation_m");
  EXPECT_NE(bar.find("converged_p50_translation_m, mm (log scale)"), std::string::npos);
  EXPECT_NE(svg_of(html, "cell-key").find(">method fails</text>"), std::string::npos);
}

TEST(SweepPage, NoValueAnywhereIsUnknownNotHolding) {
  SweepSpec spec;
  spec.scenario = "s.yaml";
  spec.axes = {parse_grid_axis("duration_s=1,2")};
  spec.methods = {"full_fusion"};
  std::vector<CellResult> cells(2);
  for (std::size_t c = 0; c < 2; ++c) {
    cells[c].cell = c;
    cells[c].stats.assign(1, std::vector<double>(sweep_statistics().size(), std::nan("")));
  }
  const std::string html = sweep_html(spec, cells);
  EXPECT_NE(html.find(">unknown (no value)</td>"), std::string::npos);
  EXPECT_EQ(html.find(">holds where known</td>"), std::string::npos);
  EXPECT_EQ(html.find(">holds</td>"), std::string::npos);
  EXPECT_NE(html.find("No cell has a value of <code>converged_p50_translation_m</code>"),
            std::string::npos);
}

}  // namespace
}  // namespace arttrack::sim
