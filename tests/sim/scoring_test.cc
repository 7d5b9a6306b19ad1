#include "arttrack/sim/scoring.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(PoseError, TranslationAndAngleAgainstConstruction) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n(0.0, 1.0);
  for (double angle : {0.0, 1e-9, 1e-6, 1e-3, 0.5, 2.0, 3.0, kPi - 1e-7, kPi}) {
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::Isometry3d T_est = Eigen::Isometry3d::Identity();
      T_est.linear() =
          Eigen::AngleAxisd(n(rng), Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized())
              .toRotationMatrix();
      T_est.translation() << n(rng), n(rng), n(rng);
      // The truth: the estimate rotated by `angle` about a random axis in its
      // own frame, and shifted by a known vector in the camera frame.
      const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
      const Eigen::Vector3d shift(0.003, -0.004, 0.012);  // 13 mm
      Eigen::Isometry3d T_true = T_est * Eigen::AngleAxisd(angle, axis);
      T_true.translation() = T_est.translation() + shift;
      const PoseError e = pose_error(T_est, T_true);
      EXPECT_NEAR(e.translation_m, 0.013, 1e-15);
      // Relative 1e-7 near 0 (acos of the trace would give 0 or ~1e-8 here),
      // absolute 1e-12 elsewhere.
      EXPECT_NEAR(e.rotation_rad, angle, std::max(1e-12, 1e-7 * angle)) << angle;
      EXPECT_GE(e.rotation_rad, 0.0);
      EXPECT_LE(e.rotation_rad, kPi);
      // Symmetric.
      EXPECT_NEAR(pose_error(T_true, T_est).rotation_rad, e.rotation_rad, 1e-12);
    }
  }
}

TEST(Percentiles, NumpyLinearByHand) {
  // numpy.percentile([3, 1, 4, 2], [1, 25, 50, 75, 99]) = 1.03 1.75 2.5 3.25 3.97
  const std::vector<double> v = {3.0, 1.0, 4.0, 2.0};
  const Percentiles p = percentiles(v);
  EXPECT_EQ(p.count, 4u);
  EXPECT_NEAR(p.p01, 1.03, 1e-12);
  EXPECT_NEAR(p.p25, 1.75, 1e-12);
  EXPECT_NEAR(p.p50, 2.5, 1e-12);
  EXPECT_NEAR(p.p75, 3.25, 1e-12);
  EXPECT_NEAR(p.p99, 3.97, 1e-12);
  EXPECT_DOUBLE_EQ(p.mean, 2.5);
  EXPECT_EQ(p.max, 4.0);
  // 0, 10, ..., 100: h = 10 q, so the q-quantile is 100 q.
  std::vector<double> w;
  for (int i = 10; i >= 0; --i) w.push_back(10.0 * i);
  const Percentiles pw = percentiles(w);
  EXPECT_NEAR(pw.p01, 1.0, 1e-12);
  EXPECT_NEAR(pw.p25, 25.0, 1e-12);
  EXPECT_NEAR(pw.p50, 50.0, 1e-12);
  EXPECT_NEAR(pw.p99, 99.0, 1e-12);
  // One value, and none.
  const Percentiles one = percentiles(std::vector<double>{0.7});
  EXPECT_EQ(one.p01, 0.7);
  EXPECT_EQ(one.p99, 0.7);
  const Percentiles none = percentiles({});
  EXPECT_EQ(none.count, 0u);
  EXPECT_TRUE(std::isnan(none.p50));
  EXPECT_TRUE(std::isnan(quantile_sorted({}, 0.5)));
}

TEST(Percentiles, LostEstimatesAreTheWorst) {
  // [1, 2, 3, NaN] -> [1, 2, 3, inf]: the median is unaffected, the top is inf.
  const Percentiles p = percentiles(std::vector<double>{2.0, NAN, 1.0, 3.0});
  EXPECT_NEAR(p.p50, 2.5, 1e-12);
  EXPECT_NEAR(p.p25, 1.75, 1e-12);
  EXPECT_TRUE(std::isinf(p.p99));
  EXPECT_TRUE(std::isinf(p.max));
  // An exact hit on a finite order statistic next to an infinite one.
  const std::vector<double> sorted = {1.0, 2.0, INFINITY};
  EXPECT_EQ(quantile_sorted(sorted, 0.5), 2.0);
}

ErrorTrace trace_of(const std::vector<double>& errors_m, double dt_s = 1.0) {
  ErrorTrace t;
  for (std::size_t i = 0; i < errors_m.size(); ++i) t.add(i * dt_s, {errors_m[i], 0.0});
  return t;
}

TEST(Scoring, TimeToConverge) {
  // Below 1 cm for good from t = 5 s (the 3 mm at t = 3 s does not count).
  const ErrorTrace t = trace_of({0.5, 0.3, 0.02, 0.003, 0.03, 0.004, 0.003, 0.002, 0.001, 0.001});
  ASSERT_TRUE(time_to_converge_s(t, 0.01).has_value());
  EXPECT_EQ(*time_to_converge_s(t, 0.01), 5.0);
  EXPECT_EQ(*time_to_converge_s(t, 0.05), 2.0);
  EXPECT_EQ(*time_to_converge_s(t, 1.0), 0.0);             // always below
  EXPECT_FALSE(time_to_converge_s(t, 0.001).has_value());  // never strictly below
  EXPECT_FALSE(time_to_converge_s(trace_of({0.001, 0.001, 0.5}), 0.01).has_value());
  EXPECT_FALSE(time_to_converge_s(trace_of({0.001, NAN}), 0.01).has_value());
  EXPECT_FALSE(time_to_converge_s(ErrorTrace(), 0.01).has_value());
}

TEST(Scoring, ShareWorseThanReferenceAtCommonTimes) {
  ErrorTrace method, reference;
  // Method sampled every 0.5 s, reference every 1 s: common times 0..4.
  const double m[] = {0.1, 9, 0.3, 9, 0.05, 9, 0.2, 9, 0.01};
  const double r[] = {0.2, 0.2, 0.2, 0.2, 0.2};
  for (int i = 0; i < 9; ++i) method.add(0.5 * i, {m[i], 0.0});
  for (int i = 0; i < 5; ++i) reference.add(1.0 * i, {r[i], 0.0});
  // At 0, 1, 2, 3, 4 s: 0.1, 0.3, 0.05, 0.2, 0.01 against 0.2: one worse (the
  // tie at 3 s is not worse).
  const ReferenceComparison c = compare_with_reference(method, reference);
  EXPECT_EQ(c.compared, 5u);
  EXPECT_EQ(c.worse, 1u);
  EXPECT_DOUBLE_EQ(c.share_worse(), 0.2);
  const ReferenceComparison late = compare_with_reference(method, reference, 1.5);
  EXPECT_EQ(late.compared, 3u);
  EXPECT_EQ(late.worse, 0u);
  EXPECT_TRUE(std::isnan(compare_with_reference(method, ErrorTrace()).share_worse()));
}

TEST(Scoring, SummaryPoolsRunsAndSplitsAtConvergence) {
  const std::vector<std::string> joints = {"a", "b"};
  MethodScores fusion("full fusion", joints), encoders("encoders only", joints);
  // Two runs of 4 samples at t = 0, 2, 4, 6 s.
  const double f[2][4] = {{0.10, 0.02, 0.004, 0.002}, {0.08, 0.006, 0.003, 0.001}};
  const double e[2][4] = {{0.05, 0.05, 0.05, 0.05}, {0.004, 0.004, 0.004, 0.004}};
  for (int run = 0; run < 2; ++run) {
    fusion.begin_run();
    encoders.begin_run();
    for (int i = 0; i < 4; ++i) {
      const std::vector<double> angle = {0.01 * (i + 1), -0.02 * (i + 1)};
      const std::vector<double> bias = {-0.1 / (i + 1), 0.0};
      fusion.add(2.0 * i, {f[run][i], 0.1 * f[run][i]}, angle, bias);
      encoders.add(2.0 * i, {e[run][i], 0.0});
    }
  }
  ScoringOptions opt;
  opt.converged_after_s = 3.0;
  opt.convergence_threshold_m = 0.01;
  const MethodSummary s = fusion.summary(opt, &encoders);
  EXPECT_EQ(s.num_runs, 2u);
  // All 8 samples sorted: .001 .002 .003 .004 .006 .02 .08 .10; median
  // (.004 + .006) / 2, 25th at h = 1.75: .002 + .75 * .001.
  EXPECT_EQ(s.all.translation_m.count, 8u);
  EXPECT_NEAR(s.all.translation_m.p50, 0.005, 1e-15);
  EXPECT_NEAR(s.all.translation_m.p25, 0.00275, 1e-15);
  EXPECT_NEAR(s.all.rotation_rad.p50, 0.0005, 1e-15);
  // From 3 s: .004 .002 .003 .001 -> median .0025, max .004.
  EXPECT_EQ(s.converged.translation_m.count, 4u);
  EXPECT_NEAR(s.converged.translation_m.p50, 0.0025, 1e-15);
  EXPECT_EQ(s.converged.translation_m.max, 0.004);
  // Per-joint absolute errors from 3 s: joint b angle |-.06|, |-.08| twice.
  ASSERT_EQ(s.converged.joint_angle_abs_error_rad.size(), 2u);
  EXPECT_NEAR(s.converged.joint_angle_abs_error_rad[1].p50, 0.07, 1e-15);
  EXPECT_NEAR(s.converged.joint_bias_abs_error_rad[0].max, 0.1 / 3, 1e-15);
  // Converged below 1 cm at 4 s in run 0, 2 s in run 1.
  ASSERT_EQ(s.time_to_converge_s.size(), 2u);
  EXPECT_EQ(s.time_to_converge_s[0], 4.0);
  EXPECT_EQ(s.time_to_converge_s[1], 2.0);
  // Worse than encoders: run 0 at t = 0 (.10 > .05); run 1 at 0 and 2 s
  // (.08, .006 > .004): 3 of 8; from 3 s none of 4.
  EXPECT_EQ(s.all.reference.compared, 8u);
  EXPECT_EQ(s.all.reference.worse, 3u);
  EXPECT_EQ(s.converged.reference.compared, 4u);
  EXPECT_EQ(s.converged.reference.worse, 0u);
  // The reference's own summary has no per-joint errors.
  const MethodSummary r = encoders.summary(opt);
  EXPECT_TRUE(r.all.joint_angle_abs_error_rad.empty());
  EXPECT_EQ(r.all.reference.compared, 0u);
  EXPECT_FALSE(r.time_to_converge_s[0].has_value());
  EXPECT_EQ(r.time_to_converge_s[1], 0.0);
}

TEST(Scoring, MergingEqualsPooling) {
  MethodScores a("vision only", {}), b("vision only", {}), all("vision only", {});
  std::mt19937_64 rng(4);
  std::exponential_distribution<double> err(100.0);
  for (int run = 0; run < 6; ++run) {
    MethodScores& part = run < 3 ? a : b;
    part.begin_run();
    all.begin_run();
    for (int i = 0; i < 50; ++i) {
      const PoseError e{err(rng), err(rng)};
      part.add(0.1 * i, e);
      all.add(0.1 * i, e);
    }
  }
  a.merge(b);
  ScoringOptions opt;
  opt.converged_after_s = 2.0;
  const MethodSummary sa = a.summary(opt), sall = all.summary(opt);
  EXPECT_EQ(sa.num_runs, 6u);
  EXPECT_EQ(sa.all.translation_m.p25, sall.all.translation_m.p25);
  EXPECT_EQ(sa.converged.rotation_rad.p99, sall.converged.rotation_rad.p99);
  EXPECT_EQ(sa.time_to_converge_s, sall.time_to_converge_s);
}

TEST(Scoring, BadInputIsNamed) {
  auto expect_error = [](auto&& f, const std::string& field) {
    try {
      f();
      ADD_FAILURE() << "no error for " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  ErrorTrace t(2);
  t.add(1.0, {0.1, 0.1});
  expect_error([&] { t.add(0.5, {0.1, 0.1}); }, "earlier");
  expect_error([&] { t.add(2.0, {0.1, 0.1}, std::vector<double>{0.1, 0.2}); }, "every sample");
  expect_error([&] { t.add(2.0, {0.1, 0.1}, std::vector<double>{0.1}); }, "expected 2");
  MethodScores m("fusion", {"a"}), ref("encoders", {"a"});
  m.add(0.0, {0.1, 0.1});
  ScoringOptions opt;
  opt.convergence_threshold_m = 0.0;
  expect_error([&] { m.summary(opt); }, "convergence_threshold_m");
  expect_error([&] { m.summary(ScoringOptions{}, &ref); }, "runs");
  expect_error([&] { m.merge(MethodScores("fusion", {"b"})); }, "different joints");
}

}  // namespace
}  // namespace arttrack::sim
