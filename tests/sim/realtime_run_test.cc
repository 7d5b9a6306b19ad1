// RunOptions::realtime: the run is simulated first, then replayed at the
// wall clock's pace to trackers that run asynchronously, and every applied image gets an end-to-end
// latency (capture to estimate) that covers its delivery delay and its
// update. Timing assertions are lower bounds only (a loaded machine can be
// slower, never faster).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "arttrack/sim/scenario_runner.h"
#include "arttrack/tracker/error.h"
#include "scenario_test_robot.h"

namespace arttrack::sim {
namespace {

// Images arrive 50 ms after capture; the tracker is small (5 particles).
constexpr char kRealtimeScenario[] = R"(
scene: scene.yaml
duration_s: 1.5
seed: 3
methods: [encoders_only, full_fusion]
motion:
  sinusoids:
    - {joints: [left_arm_joint_1], amplitude_deg: 10, frequency_hz: 0.5}
camera: {latency_s: 0.05}
tracker_overrides: {particle_filter.particles: 5}
scoring: {converged_after_s: 0.5, end_effectors: [left_ee]}
)";

TEST(RealtimeRun, PacesTheSimulationAndMeasuresTheLatencyOfEveryAppliedImage) {
  const test::TestDir dir("realtime_run");
  const Scenario scenario = load_scenario(dir.write("rt.yaml", kRealtimeScenario));
  RunOptions options;
  options.realtime = true;
  const auto start = std::chrono::steady_clock::now();
  const ScenarioResult r = run_scenario(scenario, options);
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(wall_s, 1.5);  // paced: never faster than the wall clock

  const RunResult& run = r.runs.at(0);
  const MethodRun& fusion = run.methods.at(1);
  ASSERT_EQ(fusion.method, "full_fusion");
  const TrackerStats& s = fusion.stats;
  EXPECT_EQ(s.images_received, run.frames_delivered);
  EXPECT_EQ(s.images_applied + s.images_dropped_too_old + s.images_dropped_backlog +
                s.images_dropped_busy,
            s.images_received);
  EXPECT_GT(s.images_applied, 0);
  ASSERT_EQ(s.images.size(), std::size_t(s.images_applied));
  ASSERT_EQ(fusion.image_latency_ms.size(), std::size_t(s.images_applied));
  const std::vector<double> stamps = s.images.values(&ImageTiming::stamp_s);
  EXPECT_TRUE(std::is_sorted(stamps.begin(), stamps.end()));
  for (std::size_t k = 0; k < fusion.image_latency_ms.size(); ++k) {
    // Inside the tracker: at least the update itself.
    EXPECT_GE(s.images[k].latency_ms, s.images[k].update_ms);
    // End to end: at least the 50 ms delivery delay plus the tracker's part.
    EXPECT_GE(fusion.image_latency_ms[k], 50.0 + s.images[k].latency_ms - 1e-6);
  }
  const MethodResult* m = r.method("full_fusion");
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->timing.image_latency_ms.count, fusion.image_latency_ms.size());
  EXPECT_GE(m->timing.image_latency_ms.p50, 50.0);
  // Encoders only takes no images.
  EXPECT_TRUE(run.methods.at(0).image_latency_ms.empty());
}

TEST(RealtimeRun, OffByDefaultWithoutLatencies) {
  const test::TestDir dir("realtime_off");
  const Scenario scenario = load_scenario(dir.write("rt.yaml", kRealtimeScenario));
  const ScenarioResult r = run_scenario(scenario);
  const MethodRun& fusion = r.runs.at(0).methods.at(1);
  EXPECT_TRUE(fusion.image_latency_ms.empty());
  EXPECT_EQ(r.method("full_fusion")->timing.image_latency_ms.count, 0u);
  // The tracker's own per-image figures are there in either mode.
  EXPECT_EQ(fusion.stats.images.size(), std::size_t(fusion.stats.images_applied));
}

// The replay hands over what the simulation made: encoders only (no images,
// so no timing in its estimates) scores exactly as in a run that is not
// real time, sample for sample.
TEST(RealtimeRun, ReplaysTheSimulatedMeasurementsAndTruth) {
  const test::TestDir dir("realtime_replay");
  const Scenario scenario = load_scenario(dir.write("rt.yaml", kRealtimeScenario));
  RunOptions options;
  options.methods = {"encoders_only"};
  const ScenarioResult at_once = run_scenario(scenario, options);
  options.realtime = true;
  const ScenarioResult replayed = run_scenario(scenario, options);
  const ErrorTrace& a = at_once.method_results.at(0).scores.runs().at(0);
  const ErrorTrace& b = replayed.method_results.at(0).scores.runs().at(0);
  ASSERT_GT(a.size(), 40u);
  EXPECT_EQ(a.time_s(), b.time_s());
  EXPECT_EQ(a.translation_m(), b.translation_m());
  EXPECT_EQ(a.rotation_rad(), b.rotation_rad());
  EXPECT_EQ(at_once.runs.at(0).frames_delivered, replayed.runs.at(0).frames_delivered);
}

// What the replay keeps is bounded: a run too long to keep is refused before
// it is simulated, naming the scenario and what to change.
TEST(RealtimeRun, RefusesARunTooLongToKeep) {
  const test::TestDir dir("realtime_too_long");
  const Scenario scenario =
      load_scenario(dir.write("rt.yaml", kRealtimeScenario), {"duration_s=30000"});
  RunOptions options;
  options.realtime = true;
  const auto start = std::chrono::steady_clock::now();
  try {
    run_scenario(scenario, options);
    FAIL() << "a 30000 s real-time run was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("rt.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("--realtime"), std::string::npos) << what;
    EXPECT_NE(what.find("duration_s"), std::string::npos) << what;
    EXPECT_NE(what.find("MB"), std::string::npos) << what;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
}

}  // namespace
}  // namespace arttrack::sim
