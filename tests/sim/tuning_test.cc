// Tuning tracker parameters:
//   - the optimiser wrapper finds the known minimum of quadratics in the unit
//     box (inside, and on a bound) with each of the four NLopt methods, keeps
//     to its budget and passes the objective's exceptions on;
//   - parameter and objective specifications: normalised coordinates, whole
//     numbers rounded, bad specs named in the error;
//   - a candidate configuration written as YAML loads back with its values;
//   - a tiny real search on the small robot: the first candidate is the
//     default configuration, so the tuned objective is no worse than the
//     default's, which re-running the default reproduces exactly.
#include "arttrack/sim/tuning.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "../error_of.h"
#include "../scratch_dir.h"
#include "arttrack/sim/sweep.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "scenario_test_robot.h"

namespace arttrack::sim {
namespace {

using arttrack::test_support::error_of;

namespace fs = std::filesystem;

YamlDocument default_tracker_doc() {
  return load_yaml_file(std::string(ARTTRACK_SOURCE_DIR) + "/tracker/config/default.yaml");
}

struct OptimiserCase {
  Optimizer optimizer;
  int budget;
  double tolerance;  // on the optimum's coordinates
};

class OptimiserTest : public ::testing::TestWithParam<OptimiserCase> {};

TEST_P(OptimiserTest, FindsTheMinimumOfAQuadratic) {
  const OptimiserCase c = GetParam();
  // Minimum 0.1 at (0.3, 0.7), anisotropic and correlated.
  int calls = 0;
  const auto f = [&](const std::vector<double>& u) {
    ++calls;
    EXPECT_EQ(u.size(), 2u);
    for (double x : u) {
      EXPECT_GE(x, 0.0);
      EXPECT_LE(x, 1.0);
    }
    const double a = u[0] - 0.3, b = u[1] - 0.7;
    return 0.1 + a * a + 3 * b * b + a * b;
  };
  const OptimizerResult r = minimize_unit_box(f, {0.9, 0.1}, c.optimizer, c.budget);
  EXPECT_NEAR(r.u[0], 0.3, c.tolerance) << optimizer_name(c.optimizer) << " " << r.stop;
  EXPECT_NEAR(r.u[1], 0.7, c.tolerance) << optimizer_name(c.optimizer) << " " << r.stop;
  EXPECT_NEAR(r.value, 0.1, 4 * c.tolerance * c.tolerance + 1e-9);
  EXPECT_EQ(r.evaluations, calls);
  EXPECT_LE(calls, c.budget);

  // A minimum on a bound: (1, 0.25) for a quadratic centred outside the box.
  const auto g = [](const std::vector<double>& u) {
    const double a = u[0] - 1.4, b = u[1] - 0.25;
    return a * a + b * b;
  };
  const OptimizerResult s = minimize_unit_box(g, {0.5, 0.5}, c.optimizer, c.budget);
  EXPECT_NEAR(s.u[0], 1.0, c.tolerance) << optimizer_name(c.optimizer);
  EXPECT_NEAR(s.u[1], 0.25, c.tolerance) << optimizer_name(c.optimizer);
}

INSTANTIATE_TEST_SUITE_P(AllMethods, OptimiserTest,
                         ::testing::Values(OptimiserCase{Optimizer::kBobyqa, 100, 1e-3},
                                           OptimiserCase{Optimizer::kCobyla, 200, 1e-3},
                                           OptimiserCase{Optimizer::kNelderMead, 300, 1e-3},
                                           OptimiserCase{Optimizer::kDirect, 400, 1e-2}),
                         [](const auto& info) {
                           return std::string(optimizer_name(info.param.optimizer));
                         });

TEST(Optimiser, KeepsToItsBudgetAndPassesExceptionsOn) {
  int calls = 0;
  const auto f = [&](const std::vector<double>& u) {
    ++calls;
    return std::sin(7 * u[0]) + u[0] * u[0];
  };
  const OptimizerResult r = minimize_unit_box(f, {0.5}, Optimizer::kBobyqa, 4);
  EXPECT_EQ(calls, 4);
  EXPECT_EQ(r.evaluations, 4);
  EXPECT_EQ(r.stop, "budget spent");

  const auto bad = [](const std::vector<double>&) -> double {
    throw InputError("no such scenario");
  };
  EXPECT_EQ(error_of([&] {
              minimize_unit_box(bad, {0.5, 0.5}, Optimizer::kCobyla, 10);
            }),
            "no such scenario");
  EXPECT_EQ(parse_optimizer("direct"), Optimizer::kDirect);
  EXPECT_NE(error_of([] { parse_optimizer("lbfgs"); }).find("--optimizer 'lbfgs'"),
            std::string::npos);
}

TEST(TuningParameters, NormalisedCoordinatesAndWholeNumbers) {
  const YamlDocument base = default_tracker_doc();
  const std::vector<TuningParameter> p = parse_tuning_parameters(
      {"depth_model.occlusion_prior=0.05:0.45, particle_filter.particles=10:40",
       "camera_offset.rotation_diffusion_deg_per_sqrt_s=0:1:real"},
      base);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_FALSE(p[0].integer);
  EXPECT_TRUE(p[1].integer);  // known whole-number key
  EXPECT_FALSE(p[2].integer);
  EXPECT_DOUBLE_EQ(p[0].value_at(0.5), 0.25);
  EXPECT_DOUBLE_EQ(p[0].unit_of(0.25), 0.5);
  EXPECT_DOUBLE_EQ(p[0].value_at(1.5), 0.45);  // clamped
  EXPECT_DOUBLE_EQ(p[1].value_at(0.51), 25);   // 10 + 15.3, rounded
  EXPECT_EQ(p[1].text(25), "25");
  EXPECT_EQ(parse_tuning_parameters({"timing.camera_delay_s=0:3:int"}, base)[0].integer, true);
  EXPECT_TRUE(parse_tuning_parameters({"particle_filter.min_evaluations=0:800"}, base)[0].integer);
  // Every key the tracker reads as a whole number, without a list here: the
  // parser rejects 0.5 there. (A hand list lacked these four.)
  for (const char* key : {"geometry.coarser_levels=0:4", "particle_filter.threads=1:2",
                          "acquisition.searches=1:5", "refinement.min_pixels=10:60"})
    EXPECT_TRUE(parse_tuning_parameters({key}, base)[0].integer) << key;
  EXPECT_FALSE(parse_tuning_parameters({"geometry.coarser_levels=0:4:real"}, base)[0].integer);
  EXPECT_FALSE(
      parse_tuning_parameters({"uncertainty.model_error_min_std_m=0:0.01"}, base)[0].integer);

  const std::vector<std::pair<std::string, std::string>> bad = {
      {"depth_model.occlusion_priority=0:1", "not a known key"},
      {"depth_model.occlusion_prior=0:2", "occlusion_prior"},  // 2 is out of range
      {"depth_model.occlusion_prior=0.5:0.1", "lo must be below hi"},
      {"depth_model.occlusion_prior=a:1", "lo 'a' is not a finite number"},
      {"depth_model.occlusion_prior", "expected key=lo:hi"},
      {"particle_filter.particles=10.5:40", "whole numbers"},
      {"method=0:1", "method"},
  };
  for (const auto& [spec, problem] : bad) {
    const std::string msg = error_of([&] { parse_tuning_parameters({spec}, base); });
    EXPECT_NE(msg.find("--params '" + spec + "'"), std::string::npos) << msg;
    EXPECT_NE(msg.find(problem), std::string::npos) << spec << ": " << msg;
  }
  EXPECT_NE(error_of([&] {
              parse_tuning_parameters({"depth_model.width=40:80,depth_model.width=50:60"}, base);
            }).find("given twice"),
            std::string::npos);
}

TEST(TuningObjective, Parses) {
  const Objective o = parse_objective("mean_converged_p75_translation_m");
  EXPECT_EQ(o.aggregate, Objective::Aggregate::kMean);
  EXPECT_EQ(o.statistic, "converged_p75_translation_m");
  EXPECT_EQ(o.text(), "mean_converged_p75_translation_m");
  EXPECT_EQ(parse_objective("max_convergence_time_s").aggregate, Objective::Aggregate::kMax);
  for (const char* bad : {"converged_p75_translation_m", "mean_p80_translation_m", "mean_"})
    EXPECT_NE(error_of([&] { parse_objective(bad); }).find(std::string("--objective '") + bad),
              std::string::npos)
        << bad;

  // Mean or max over scenarios, plus the time penalty.
  ScenarioOutcome a, b;
  a.objective_statistic = 0.01;
  a.image_update_p50_ms = 4;
  b.objective_statistic = 0.03;
  b.image_update_p50_ms = 6;
  Objective mean = o;
  mean.time_penalty_per_ms = 0.001;
  EXPECT_DOUBLE_EQ(objective_value(mean, {a, b}), 0.02 + 0.005);
  EXPECT_DOUBLE_EQ(objective_value(parse_objective("max_p50_translation_m"), {a, b}), 0.03);
}

TEST(TuningCandidates, WrittenYamlLoadsWithItsValues) {
  const YamlDocument base = default_tracker_doc();
  const auto p = parse_tuning_parameters(
      {"depth_model.occlusion_prior=0.05:0.45,particle_filter.particles=10:40,"
       "joints.defaults.bias_diffusion_deg_per_sqrt_s=0.5:10"},
      base);
  const YamlDocument doc = candidate_document(base, p, {0.3125, 33, 1.75});
  const test_support::ScratchDir scratch("tuning_test");
  const fs::path file =
      scratch.write("candidate.yaml", tracker_yaml_text(doc, "a comment\nof two lines"));
  const TrackerConfig c = load_tracker_config(file.string());
  EXPECT_DOUBLE_EQ(c.depth_model.occlusion_prior, 0.3125);
  EXPECT_EQ(c.particle_filter.num_particles, 33);
  EXPECT_NEAR(c.joint_defaults.bias_diffusion_rad_per_sqrt_s, 1.75 * M_PI / 180, 1e-12);
  // Untouched keys keep the base's values.
  const TrackerConfig d = tracker_config_from_yaml(base);
  EXPECT_EQ(c.depth_model.width, d.depth_model.width);
  EXPECT_DOUBLE_EQ(c.camera_rotation.diffusion_per_sqrt_s, d.camera_rotation.diffusion_per_sqrt_s);
  double v = 0;
  EXPECT_TRUE(document_number(doc, "particle_filter.particles", v));
  EXPECT_EQ(v, 33);
  EXPECT_FALSE(document_number(doc, "particle_filter.blocks", v));
  // Reading leaves the document as it was.
  EXPECT_EQ(tracker_config_from_yaml(doc).particle_filter.num_particles, 33);
}

const std::string kTinyScenario = test::short_scenario(3, "[full_fusion]");

TEST(Tuning, TinySearchIsNoWorseThanTheDefault) {
  const test::TestDir dir("tuning_search");
  TuningOptions o;
  o.scenarios = {dir.write("tiny.yaml", kTinyScenario)};
  o.base_config = fs::path(ARTTRACK_SOURCE_DIR) / "tracker/config/default.yaml";
  o.parameter_specs = {"depth_model.occlusion_prior=0.1:0.5"};
  o.objective = parse_objective("mean_converged_p75_translation_m");
  o.optimizer = Optimizer::kBobyqa;
  o.budget = 2;
  o.out_dir = dir.path() / "out";
  const TuningResult r = tune(o);

  ASSERT_EQ(r.history.size(), 2u);
  // The search starts at the base configuration's value.
  EXPECT_EQ(r.default_values[0], 0.25);
  EXPECT_EQ(r.history[0].values[0], 0.25);
  EXPECT_NE(r.history[1].values[0], 0.25);
  for (const Evaluation& e : r.history) {
    EXPECT_FALSE(e.outcomes[0].failed) << e.outcomes[0].message;
    EXPECT_GT(e.objective, 0);
    EXPECT_LT(e.objective, 0.2);  // metres: tracking, not lost
  }
  EXPECT_LE(r.history[r.best].objective, r.history[0].objective);
  EXPECT_LE(r.history[r.best].objective, r.history[1].objective);
  // Re-running the default reproduces evaluation 1 exactly; tuned is no worse.
  ASSERT_EQ(r.compare_default.size(), 1u);
  EXPECT_EQ(r.compare_default[0].objective_statistic, r.history[0].outcomes[0].objective_statistic);
  EXPECT_LE(r.compare_tuned[0].objective_statistic, r.compare_default[0].objective_statistic);

  // Outputs: a loadable tuned.yaml with the best value, the search, the report.
  const TrackerConfig tuned = load_tracker_config((o.out_dir / "tuned.yaml").string());
  EXPECT_DOUBLE_EQ(tuned.depth_model.occlusion_prior, r.history[r.best].values[0]);
  std::ifstream csv(o.out_dir / "search.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(
      header,
      "evaluation,depth_model.occlusion_prior,objective,cached,tiny:converged_p75_translation_m,"
      "tiny:p50_image_update_ms,status");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 2);
  EXPECT_TRUE(fs::exists(o.out_dir / "tuning.html"));
  EXPECT_TRUE(fs::exists(o.out_dir / "candidates" / "eval_0001.yaml"));
}

// A search made by hand (no simulation): four evaluations of one scenario,
// the third failed; the best is the second.
TEST(TuningPage, SearchChartHasTicksUnitAndLegendAndWallTimesAreNotJudged) {
  TuningOptions o;
  o.scenarios = {"a.yaml"};
  o.base_config = "base.yaml";
  o.objective = parse_objective("mean_converged_p75_translation_m");
  o.budget = 4;
  TuningResult r;
  TuningParameter p;
  p.key = "depth_model.occlusion_prior";
  p.lo = 0.1;
  p.hi = 0.5;
  r.params = {p};
  r.default_values = {0.25};
  const auto outcome = [](double statistic_m, double ms) {
    ScenarioOutcome s;
    s.scenario = "a.yaml";
    s.name = "a";
    s.seed = 7;
    s.stats.assign(outcome_statistics().size(), statistic_m);
    s.stats.back() = ms;  // p50_image_update_ms
    s.objective_statistic = statistic_m;
    s.image_update_p50_ms = ms;
    return s;
  };
  const double objectives[] = {0.006, 0.004, kFailedStatistic, 0.005};
  for (int i = 0; i < 4; ++i) {
    Evaluation e;
    e.index = i + 1;
    e.values = {0.1 + 0.1 * i};
    e.outcomes = {outcome(objectives[i], 10 + i)};
    e.outcomes[0].failed = objectives[i] == kFailedStatistic;
    e.objective = objectives[i];
    r.history.push_back(e);
  }
  r.best = 1;
  r.optimizer.stop = "budget spent";
  r.compare_default = {outcome(0.006, 10)};
  r.compare_tuned = {outcome(0.004, 12)};
  r.compare_is_validation = {false};
  const std::string html = tuning_html(o, r);

  const std::size_t at = html.find("data-chart=\"search\"");
  ASSERT_NE(at, std::string::npos);
  const std::string svg = html.substr(at, html.find("</svg>", at) - at);
  for (const char* t : {">1</text>", ">2</text>", ">3</text>", ">4</text>", ">evaluation</text>",
                        ">objective, mm</text>", ">best so far</text>",
                        ">best (evaluation 2)</text>", "failed or no value"})
    EXPECT_NE(svg.find(t), std::string::npos) << t;
  // The y axis spans the evaluations that gave a value (4 to 6 mm), not the
  // failed one's 1000 m.
  EXPECT_NE(svg.find(">6.0</text>"), std::string::npos);
  EXPECT_EQ(svg.find("000000"), std::string::npos);
  // The wall time's change is shown and not judged; the errors' are.
  const std::size_t row = html.find("image update p50 (ms)");
  ASSERT_NE(row, std::string::npos);
  const std::string timing = html.substr(row, html.find("</tr>", row) - row);
  EXPECT_NE(timing.find("+20% (wall time)"), std::string::npos) << timing;
  EXPECT_EQ(timing.find("better"), std::string::npos);
  EXPECT_EQ(timing.find("worse"), std::string::npos);
  const std::size_t p50 = html.find("translation p50 (mm)");
  EXPECT_NE(html.substr(p50, html.find("</tr>", p50) - p50).find("better"), std::string::npos);
}

}  // namespace
}  // namespace arttrack::sim
