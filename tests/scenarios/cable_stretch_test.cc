// The ARM robot's cable stretch (scenarios/cable_stretch/, paper Sec. V-A):
// the encoders sit at the motors, so the stretch of the cables under the
// joints' torques is a bias they cannot see. Short runs (short_run.h) check
// that the simulated bias really changes with contact and load, and that
// full fusion follows it where encoders only cannot.
//
// Thresholds from measured values with a margin (one run, the file's seed);
// the measured values are in the comments.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "short_run.h"

namespace arttrack::sim::test {
namespace {

// Mean over the samples of run 0 with time in [from_s, to_s] of the true
// bias of `joint` (truth), or of |estimate - truth| of a method's bias.
double mean_true_bias(const ScenarioResult& r, const std::string& joint, double from_s,
                      double to_s) {
  const std::size_t j = joint_index(r, joint);
  double sum = 0;
  int n = 0;
  for (const TruthSample& t : r.runs[0].truth)
    if (t.time_s >= from_s && t.time_s <= to_s) sum += t.bias_rad[j], ++n;
  return n ? sum / n : std::numeric_limits<double>::quiet_NaN();
}
double mean_bias_error(const ScenarioResult& r, const std::string& name, const std::string& joint,
                       double from_s, double to_s) {
  const std::size_t j = joint_index(r, joint);
  std::size_t m = 0;
  while (m < r.methods.size() && r.methods[m] != name) ++m;
  if (m == r.methods.size()) throw std::runtime_error("no results for method " + name);
  const RunResult& run = r.runs[0];
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < run.truth.size(); ++i)
    if (run.truth[i].time_s >= from_s && run.truth[i].time_s <= to_s)
      sum += std::abs(run.methods[m].samples[i].bias_rad[j] - run.truth[i].bias_rad[j]), ++n;
  return n ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

// The hand comes down onto the table at 5 s and presses on it until 9 s
// (table_touch.yaml): the shoulder's bias jumps by degrees; full fusion's
// bias estimate follows it within a degree and keeps the hand at
// millimetres, encoders only is centimetres off.
TEST(CableStretch, TableContactStretchesTheCablesFullFusionFollows) {
  const ScenarioResult r =
      run_short("cable_stretch/table_touch", 11, {"encoders_only", "full_fusion"});
  const std::string shoulder = "left_arm_joint_2";
  const double free = mean_true_bias(r, shoulder, 1.5, 3);
  const double pressing = mean_true_bias(r, shoulder, 5.5, 8.5);
  const double fusion_error = mean_bias_error(r, "full_fusion", shoulder, 5.5, 8.5);
  std::cout << shoulder << " true bias free " << free / kRadPerDeg << " deg, pressing "
            << pressing / kRadPerDeg << " deg; full fusion's bias error pressing "
            << fusion_error / kRadPerDeg << " deg\n";
  // Measured: shoulder bias -2.6 deg free, +2.8 deg on average while
  // pressing (+5.1 deg at first); full fusion's bias error 0.18 deg.
  EXPECT_GT(pressing - free, 3 * kRadPerDeg);
  EXPECT_LT(fusion_error, 1 * kRadPerDeg);
  EXPECT_LT(fusion_error, (pressing - free) / 4);

  const Percentiles encoders = window(r, "encoders_only", 5.5, 8.5);
  const Percentiles fusion = window(r, "full_fusion", 5.5, 8.5);
  const Percentiles fusion_all = window(r, "full_fusion", 3, 11);
  // Measured while pressing: p50 encoders only 42.5 mm, full fusion 4.3 mm
  // (p99 6.0); from 3 to 11 s full fusion p99 13.0 mm.
  EXPECT_GT(encoders.p50, 30 * kMm);
  EXPECT_LT(fusion.p50, 10 * kMm);
  EXPECT_LT(fusion.p50, encoders.p50 / 4);
  EXPECT_LT(fusion_all.p99, 25 * kMm);
}

// What pick_and_place.yaml's loads change in the true bias of the shoulder's
// first two joints, on average while a load is lifted (from lifted_from_s to
// lifted_to_s): the scenario run up to lifted_to_s with its loads and again
// without them. Truth only: encoders only and a few camera frames (5 Hz, the
// instants scored) are enough.
std::vector<std::pair<std::string, double>> bias_change_by_loads(double lifted_from_s,
                                                                 double lifted_to_s) {
  const ScenarioResult loaded = run_short("cable_stretch/pick_and_place", lifted_to_s,
                                          {"encoders_only"}, {"camera.rate_hz=5"});
  const ScenarioResult empty = run_short("cable_stretch/pick_and_place", lifted_to_s,
                                         {"encoders_only"}, {"camera.rate_hz=5", "loads=[]"});
  std::vector<std::pair<std::string, double>> change_rad;
  for (const std::string joint : {"left_arm_joint_1", "left_arm_joint_2"})
    change_rad.emplace_back(joint, mean_true_bias(loaded, joint, lifted_from_s, lifted_to_s) -
                                       mean_true_bias(empty, joint, lifted_from_s, lifted_to_s));
  return change_rad;
}

// Carrying the 3 kg load (pick_and_place.yaml, second lift: the hand holds
// it from 29.5 s to 42.5 s, lifted from 33 s to 37 s) stretches the
// shoulder's cables: the true bias differs from the same motion without the
// load.
TEST(CableStretch, LoadStretchesTheCables) {
  for (const auto& [joint, change] : bias_change_by_loads(33, 37)) {
    std::cout << joint << ": the load changes the bias by " << change / kRadPerDeg << " deg\n";
    // Measured: -1.25 deg on joint 1, -1.23 deg on joint 2.
    EXPECT_GT(std::abs(change), 0.8 * kRadPerDeg) << joint;
  }
}

// The same for the first lift (the load held from 4.5 s to 17.5 s, lifted
// from 8 s to 12 s), with a second load on the same link not picked up yet
// (weight 0 until 29.5 s): loads on one link add up. (When the runner set
// each load's force instead, the second overwrote the first: change 0 deg.)
TEST(CableStretch, EveryLoadStretchesTheCables) {
  for (const auto& [joint, change] : bias_change_by_loads(8, 12)) {
    std::cout << joint << ": the first load changes the bias by " << change / kRadPerDeg
              << " deg\n";
    EXPECT_GT(std::abs(change), 0.8 * kRadPerDeg) << joint;
  }
}

}  // namespace
}  // namespace arttrack::sim::test
