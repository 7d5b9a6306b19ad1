// A check shared by the tests that feed one run's measurements to trackers
// twice (replayed in memory, or exported and tracked from files).
#pragma once

#include <gtest/gtest.h>

#include <cmath>

#include "arttrack/sim/scenario_runner.h"

namespace arttrack::sim::test {

// Both NaN (e.g. no converged samples), or within `tolerance`.
inline ::testing::AssertionResult same_statistic(double a, double b, double tolerance) {
  if ((std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= tolerance)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " and " << b << " differ by more than " << tolerance;
}

// Per method of run 0: bit for bit the same estimated angles, biases and
// camera offsets at every scored instant (the same inputs in the same
// order), the same tracker counts, and end-effector errors and summaries
// within the tolerances (0: exact; a dataset's truth went through a
// quaternion).
inline void expect_same_tracking(const ScenarioResult& a_result, const ScenarioResult& b_result,
                                 double tolerance_m, double tolerance_rad) {
  const RunResult& a = a_result.runs.at(0);
  const RunResult& b = b_result.runs.at(0);
  ASSERT_EQ(b.methods.size(), a.methods.size());
  for (std::size_t m = 0; m < a.methods.size(); ++m) {
    SCOPED_TRACE(a.methods[m].method);
    EXPECT_EQ(b.methods[m].method, a.methods[m].method);
    ASSERT_EQ(b.methods[m].samples.size(), a.methods[m].samples.size());
    for (std::size_t i = 0; i < a.methods[m].samples.size(); ++i) {
      const EstimateSample& x = a.methods[m].samples[i];
      const EstimateSample& y = b.methods[m].samples[i];
      ASSERT_EQ(y.angle_rad, x.angle_rad) << "sample " << i;
      ASSERT_EQ(y.bias_rad, x.bias_rad) << "sample " << i;
      ASSERT_EQ(y.camera_offset, x.camera_offset) << "sample " << i;
      ASSERT_EQ(y.ee_error.size(), x.ee_error.size());
      for (std::size_t e = 0; e < x.ee_error.size(); ++e) {
        EXPECT_NEAR(y.ee_error[e].translation_m, x.ee_error[e].translation_m, tolerance_m);
        EXPECT_NEAR(y.ee_error[e].rotation_rad, x.ee_error[e].rotation_rad, tolerance_rad);
      }
    }
    const TrackerStats& sa = a.methods[m].stats;
    const TrackerStats& sb = b.methods[m].stats;
    EXPECT_EQ(sb.joint_measurements, sa.joint_measurements);
    EXPECT_EQ(sb.images_received, sa.images_received);
    EXPECT_EQ(sb.images_applied, sa.images_applied);
    EXPECT_EQ(sb.likelihood_evaluations, sa.likelihood_evaluations);
    const MethodSummary& pa = a_result.method_results.at(m).summary;
    const MethodSummary& pb = b_result.method_results.at(m).summary;
    EXPECT_TRUE(same_statistic(pb.all.translation_m.p50, pa.all.translation_m.p50, tolerance_m));
    EXPECT_TRUE(same_statistic(pb.all.translation_m.p99, pa.all.translation_m.p99, tolerance_m));
    EXPECT_TRUE(same_statistic(pb.converged.rotation_rad.p50, pa.converged.rotation_rad.p50,
                               tolerance_rad));
    EXPECT_EQ(pb.time_to_converge_s, pa.time_to_converge_s);
    EXPECT_EQ(pb.all.reference.worse, pa.all.reference.worse);
  }
}

}  // namespace arttrack::sim::test
