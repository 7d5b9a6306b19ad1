#include "arttrack/sim/scoring.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "../expect_error.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "scenario_test_robot.h"

namespace arttrack::sim {
namespace {

using test_support::expect_error_naming;

// A random pose and a random unit axis.
Eigen::Vector3d random_axis(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
}
Eigen::Isometry3d random_pose(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(n(rng), random_axis(rng)).toRotationMatrix();
  T.translation() << n(rng), n(rng), n(rng);
  return T;
}

TEST(PoseError, TranslationAndAngleAgainstConstruction) {
  std::mt19937_64 rng(1);
  for (double angle :
       {0.0, 1e-9, 1e-6, 1e-3, 0.5, 2.0, 3.0, std::numbers::pi - 1e-7, std::numbers::pi}) {
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Isometry3d T_est = random_pose(rng);
      // The truth: the estimate rotated by `angle` about a random axis in its
      // own frame, and shifted by a known vector in the camera frame.
      const Eigen::Vector3d axis = random_axis(rng);
      const Eigen::Vector3d shift(0.003, -0.004, 0.012);  // 13 mm
      Eigen::Isometry3d T_true = T_est * Eigen::AngleAxisd(angle, axis);
      T_true.translation() = T_est.translation() + shift;
      const PoseError e = pose_error(T_est, T_true);
      EXPECT_NEAR(e.translation_m, 0.013, 1e-15);
      // Relative 1e-7 near 0 (acos of the trace would give 0 or ~1e-8 here),
      // absolute 1e-12 elsewhere.
      EXPECT_NEAR(e.rotation_rad, angle, std::max(1e-12, 1e-7 * angle)) << angle;
      EXPECT_GE(e.rotation_rad, 0.0);
      EXPECT_LE(e.rotation_rad, std::numbers::pi);
      // Symmetric.
      EXPECT_NEAR(pose_error(T_true, T_est).rotation_rad, e.rotation_rad, 1e-12);
    }
  }
}

TEST(PoseError, VectorIsTheEstimateMinusTheTruthInTheCameraAxes) {
  std::mt19937_64 rng(2);
  for (double angle : {0.0, 1e-9, 1e-4, 0.3, 2.5, std::numbers::pi - 1e-6}) {
    const Eigen::Isometry3d T_true = random_pose(rng);
    // The estimate: the truth turned by a known rotation vector in the
    // camera frame (left), and shifted by a known vector.
    const Eigen::Vector3d axis = random_axis(rng);
    const Eigen::Vector3d shift(0.002, 0.0, -0.005);
    Eigen::Isometry3d T_est = T_true;
    T_est.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix() * T_true.linear();
    T_est.translation() += shift;
    const PoseErrorVector v = pose_error_vector(T_est, T_true);
    EXPECT_TRUE(v.head<3>().isApprox(shift, 1e-12)) << v.transpose();
    EXPECT_NEAR((v.tail<3>() - angle * axis).norm(), 0.0, std::max(1e-12, 1e-7 * angle)) << angle;
    EXPECT_NEAR(v.tail<3>().norm(), pose_error(T_est, T_true).rotation_rad, 1e-12);
    // The other way round: the opposite error.
    EXPECT_TRUE((pose_error_vector(T_true, T_est) + v).isZero(1e-9)) << angle;
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

// A trace sampled every 10 ms from 9 s to 13 s whose error is 5 mm except
// above `level_m` for t in [from_s, to_s] (both ends sampled).
ErrorTrace stretch_trace(double from_s, double to_s, double level_m = 0.03) {
  ErrorTrace t;
  for (int i = 900; i <= 1300; ++i) {
    const double time = 0.01 * i;
    const bool above = time >= from_s - 1e-9 && time <= to_s + 1e-9;
    t.add(time, {above ? level_m : 0.005, 0.0});
  }
  return t;
}

TEST(Scoring, LostOnlyAfterMoreThanTheTimeAboveTheThreshold) {
  ScoringOptions opt;  // defaults: 2 cm for more than 1 s, from 10 s on
  ASSERT_EQ(opt.lost_threshold_m, 0.02);
  ASSERT_EQ(opt.lost_after_s, 1.0);
  ASSERT_EQ(opt.converged_after_s, 10.0);
  // 0.99 s above (10.00 .. 10.99): not lost; 1.01 s (10.00 .. 11.01): lost.
  EXPECT_FALSE(lost_span(stretch_trace(10.0, 10.99), opt).has_value());
  const std::optional<LostSpan> lost = lost_span(stretch_trace(10.0, 11.01), opt);
  ASSERT_TRUE(lost.has_value());
  EXPECT_NEAR(lost->from_s, 10.0, 1e-12);
  EXPECT_NEAR(lost->duration_s, 1.01, 1e-9);
  // Exactly at the threshold is not above it; just over it is.
  EXPECT_FALSE(lost_span(stretch_trace(10.0, 12.0, 0.02), opt).has_value());
  EXPECT_TRUE(lost_span(stretch_trace(10.0, 12.0, 0.0201), opt).has_value());
  // Only what happens from converged_after_s on counts: 9.0 .. 10.99 is
  // 0.99 s after 10 s; 9.0 .. 11.01 is 1.01 s.
  EXPECT_FALSE(lost_span(stretch_trace(9.0, 10.99), opt).has_value());
  const std::optional<LostSpan> late = lost_span(stretch_trace(9.0, 11.01), opt);
  ASSERT_TRUE(late.has_value());
  EXPECT_NEAR(late->from_s, 10.0, 1e-12);
  // A stretch running to the end of the trace: 11.5 .. 13.
  const std::optional<LostSpan> end = lost_span(stretch_trace(11.5, 14.0), opt);
  ASSERT_TRUE(end.has_value());
  EXPECT_NEAR(end->duration_s, 1.5, 1e-9);
  // One sample below breaks a stretch: 10.0 .. 10.6 and 10.62 .. 11.3.
  ErrorTrace broken;
  for (int i = 1000; i <= 1130; ++i) broken.add(0.01 * i, {i == 1061 ? 0.001 : 0.05, 0.0});
  EXPECT_FALSE(lost_span(broken, opt).has_value());
  // A lost estimate (NaN) is above any threshold.
  ErrorTrace nan;
  for (int i = 1000; i <= 1200; ++i) nan.add(0.01 * i, {i >= 1050 ? NAN : 0.001, 0.0});
  EXPECT_TRUE(lost_span(nan, opt).has_value());
  // Other keys move the edges.
  ScoringOptions strict = opt;
  strict.lost_after_s = 0.5;
  EXPECT_TRUE(lost_span(stretch_trace(10.0, 10.51), strict).has_value());
  strict.lost_threshold_m = 0.05;
  EXPECT_FALSE(lost_span(stretch_trace(10.0, 12.0), strict).has_value());
}

// A run lost again after it came back says so: the first stretch, with the
// count and total time of every stretch that counts as lost.
TEST(Scoring, LostSpanCountsEveryStretchThatCountsAsLost) {
  const ScoringOptions opt;  // 2 cm for more than 1 s, from 10 s on
  // Above from 10.0 to 11.5 s, 0.5 s (not lost) from 12.0 s, and 2 s from
  // 13.0 to 15.0 s; below otherwise, to 16 s.
  ErrorTrace t;
  for (int i = 1000; i <= 1600; ++i) {
    const bool above = (i <= 1150) || (i >= 1200 && i <= 1250) || (i >= 1300 && i <= 1500);
    t.add(0.01 * i, {above ? 0.05 : 0.001, 0.0});
  }
  const std::optional<LostSpan> lost = lost_span(t, opt);
  ASSERT_TRUE(lost.has_value());
  EXPECT_NEAR(lost->from_s, 10.0, 1e-9);
  EXPECT_NEAR(lost->duration_s, 1.5, 1e-9);
  EXPECT_EQ(lost->stretches, 2);
  EXPECT_NEAR(lost->total_s, 3.5, 1e-9);
  EXPECT_EQ(more_stretches_note(*lost), "2 stretches, 3.5 s in all");
  EXPECT_EQ(lost_span_notes(*lost), "2 stretches, 3.5 s in all");  // no view flags: one note
  LostSpan both_notes = *lost;
  both_notes.out_of_view_share = 0.25;
  EXPECT_EQ(lost_span_notes(both_notes),
            "out of the camera's view for 25% of it; 2 stretches, 3.5 s in all");
  // One stretch: its own duration, and no note.
  const std::optional<LostSpan> one = lost_span(stretch_trace(10.0, 11.5), opt);
  ASSERT_TRUE(one.has_value());
  EXPECT_EQ(one->stretches, 1);
  EXPECT_NEAR(one->total_s, 1.5, 1e-9);
  EXPECT_EQ(more_stretches_note(*one), "");
  EXPECT_EQ(lost_span_notes(*one), "");
}

// A lost span says how much of it the end effector was out of view: an arm
// no image can see is lost for another reason than one in a wrong mode.
TEST(Scoring, LostSpanCountsTheSamplesOutOfView) {
  const ScoringOptions opt;
  // Two end effectors, 10 ms apart from 10 s: the second is 3 cm off from
  // 11.0 s to 12.99 s and out of view from 12.5 s (50 of its 200 samples);
  // the first is never off and always in view.
  ErrorTrace two(0, 2);
  for (int i = 1000; i <= 1400; ++i) {
    ScoredSample x;
    x.time_s = 0.01 * i;
    const bool off = i >= 1100 && i < 1300;
    x.end_effectors = {{0.001, 0.0}, {off ? 0.03 : 0.001, 0.0}};
    x.end_effector_in_view = {true, i < 1250};
    two.add(x);
  }
  ASSERT_TRUE(two.has_in_view());
  const std::optional<LostSpan> lost = lost_span(two.end_effector(1), opt);
  ASSERT_TRUE(lost.has_value());
  EXPECT_NEAR(lost->from_s, 11.0, 1e-9);
  EXPECT_DOUBLE_EQ(lost->out_of_view_share, 0.25);
  EXPECT_EQ(out_of_view_note(*lost), "out of the camera's view for 25% of it");
  EXPECT_FALSE(lost_span(two.end_effector(0), opt).has_value());
  // The worst of several end effectors has no single view.
  EXPECT_TRUE(std::isnan(lost_span(two, opt)->out_of_view_share));
  // A trace without view flags: not known, and no note.
  const std::optional<LostSpan> unknown = lost_span(stretch_trace(10.0, 12.0), opt);
  ASSERT_TRUE(unknown.has_value());
  EXPECT_TRUE(std::isnan(unknown->out_of_view_share));
  EXPECT_EQ(out_of_view_note(*unknown), "");
  // In view throughout: no note either.
  EXPECT_EQ(out_of_view_note(LostSpan{10.0, 2.0, 0.0}), "");
  // Only the stretch's own samples count, not one before it at the same time.
  ErrorTrace same_time(0, 1);
  for (int i = 1000; i <= 1150; ++i) {
    ScoredSample x;
    x.time_s = 0.01 * i;
    x.end_effectors = {{0.03, 0.0}};
    x.end_effector_in_view = {true};
    if (i == 1000) {  // below the threshold and out of view, then above at 10 s
      ScoredSample before = x;
      before.end_effectors = {{0.001, 0.0}};
      before.end_effector_in_view = {false};
      same_time.add(before);
    }
    same_time.add(x);
  }
  const std::optional<LostSpan> in_view = lost_span(same_time, opt);
  ASSERT_TRUE(in_view.has_value());
  EXPECT_EQ(in_view->out_of_view_share, 0.0);
  // View flags are all or nothing, one per end effector.
  ScoredSample bad;
  bad.time_s = 20;
  bad.end_effectors = {{0.001, 0.0}, {0.001, 0.0}};
  EXPECT_THROW(two.add(bad), InputError);
  bad.end_effector_in_view = {true};
  EXPECT_THROW(two.add(bad), InputError);
}

// In view: in front of the camera and projecting into the image.
TEST(Scoring, InCameraViewIsInFrontAndInsideTheImage) {
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, std::numbers::pi / 4);
  EXPECT_TRUE(in_camera_view({0, 0, 1}, camera));
  EXPECT_FALSE(in_camera_view({0, 0, -1}, camera));  // behind
  EXPECT_FALSE(in_camera_view({0, 0, 0}, camera));
  // The image's right edge is at u = 80: x / z = (80 - cx) / fx.
  const double edge = (80 - camera.cx) / camera.fx;
  EXPECT_TRUE(in_camera_view({0.999 * edge, 0, 1}, camera));
  EXPECT_FALSE(in_camera_view({1.001 * edge, 0, 1}, camera));
  EXPECT_FALSE(in_camera_view({0, 1.001 * (60 - camera.cy) / camera.fy, 1}, camera));
  EXPECT_FALSE(in_camera_view({NAN, 0, 1}, camera));
}

// Two end effectors: a good left hand and a right hand that is lost in run 1.
MethodScores two_hands(const std::string& method, double right_m_run1) {
  MethodScores m(method, {}, {"left_ee", "right_ee"});
  for (int run = 0; run < 2; ++run) {
    m.begin_run();
    for (int i = 0; i <= 40; ++i) {
      ScoredSample x;
      x.time_s = 0.5 * i;                                             // 0 .. 20 s
      const double left = 0.001 * (1 + i % 4);                        // 1 .. 4 mm
      const double right = run == 1 && x.time_s >= 12 ? right_m_run1  // lost from 12 s
                                                      : 0.0005 * (1 + i % 3);
      x.end_effectors = {{left, 0.01}, {right, i == 7 ? 0.5 : 0.002}};
      m.add(x);
    }
  }
  return m;
}

TEST(Scoring, EachEndEffectorHasItsOwnStatisticsAndTheWorstPoolsThem) {
  const MethodScores fusion = two_hands("full_fusion", 0.3);
  const MethodScores encoders = two_hands("encoders_only", 0.004);
  ScoringOptions opt;
  const MethodSummary s = fusion.summary(opt, &encoders);
  ASSERT_EQ(s.end_effectors.size(), 2u);
  EXPECT_EQ(s.end_effectors[0].name, "left_ee");
  EXPECT_EQ(s.end_effectors[1].name, "right_ee");
  const EndEffectorSummary &left = s.end_effectors[0], &right = s.end_effectors[1];
  // One sample per instant and end effector: 41 per run.
  EXPECT_EQ(left.all.translation_m.count, 82u);
  EXPECT_EQ(right.all.translation_m.count, 82u);
  EXPECT_EQ(s.all.translation_m.count, 82u);
  // The left hand alone never exceeds 4 mm; the right one reaches 300 mm.
  EXPECT_EQ(left.all.translation_m.max, 0.004);
  EXPECT_EQ(right.all.translation_m.max, 0.3);
  // The worst is per sample: run 1 from 12 s on is 300 mm (17 samples of
  // 82), everything else the left hand's 1..4 mm or the right's 0.5..1.5 mm.
  EXPECT_EQ(s.all.translation_m.max, 0.3);
  std::vector<double> worst;
  for (const ErrorTrace& run : fusion.runs())
    for (std::size_t i = 0; i < run.size(); ++i) {
      const ErrorTrace l = run.end_effector(0), r = run.end_effector(1);
      EXPECT_EQ(run.translation_m()[i], std::max(l.translation_m()[i], r.translation_m()[i]));
      EXPECT_EQ(run.rotation_rad()[i], std::max(l.rotation_rad()[i], r.rotation_rad()[i]));
      worst.push_back(run.translation_m()[i]);
    }
  EXPECT_EQ(std::count(worst.begin(), worst.end(), 0.3), 17);
  EXPECT_EQ(s.all.translation_m.p50, percentiles(worst).p50);
  // Rotation's worst is taken on its own: the right hand's 0.5 rad at i = 7.
  EXPECT_EQ(s.all.rotation_rad.max, 0.5);
  // Lost: the right hand in run 1 (12 .. 20 s), not the left; one run of two.
  EXPECT_FALSE(left.lost[0] || left.lost[1]);
  EXPECT_FALSE(right.lost[0].has_value());
  ASSERT_TRUE(right.lost[1].has_value());
  EXPECT_EQ(right.lost[1]->from_s, 12.0);
  EXPECT_EQ(right.lost[1]->duration_s, 8.0);
  EXPECT_EQ(s.lost_runs(), 1u);
  EXPECT_FALSE(s.run_lost(0));
  EXPECT_TRUE(s.run_lost(1));
  // Convergence below 1 cm: the left hand at 0 s in both runs; the right
  // one never in run 1, and the worst neither.
  EXPECT_EQ(left.time_to_converge_s[1], 0.0);
  EXPECT_FALSE(right.time_to_converge_s[1].has_value());
  EXPECT_FALSE(s.time_to_converge_s[1].has_value());
  EXPECT_EQ(s.time_to_converge_s[0], 0.0);
  // Against the reference, each hand against the same hand: the left hands
  // tie, the lost right hand is worse 17 times.
  EXPECT_EQ(left.all.reference.worse, 0u);
  EXPECT_EQ(right.all.reference.worse, 17u);
  EXPECT_EQ(s.all.reference.worse, 17u);
  // Another set of end effectors cannot be a reference or be merged.
  MethodScores one("x", {}, {"left_ee"});
  one.begin_run();
  one.begin_run();
  EXPECT_THROW(fusion.summary(opt, &one), InputError);
  MethodScores copy = fusion;
  EXPECT_THROW(copy.merge(one), InputError);
}

TEST(Scoring, ConsistencyCountsTheTruthWithinTwoReportedSigmas) {
  // Joint a: errors 0, 0.04, ..., 3.96 with sigma 1: within 2 sigma for the
  // 51 errors up to 2.0. Joint b: not estimated (sigma 0). Bias of a: NaN
  // errors (lost) in 10 samples, else 0. Camera: sigma 0.5 on x, error 1.5
  // (outside); 0 elsewhere.
  ErrorTrace t(2);
  for (int i = 0; i < 100; ++i) {
    ScoredSample x;
    x.time_s = 0.1 * i;
    x.end_effectors = {{0.001, 0.001}};
    x.angle_error_rad = {0.04 * i, 5.0};
    x.angle_std_rad = {1.0, 0.0};
    x.bias_error_rad = {i < 10 ? NAN : 0.0, 0.0};
    x.bias_std_rad = {0.1, 0.0};
    x.camera = PoseError{0.02, 0.01};
    x.camera_offset_error = {1.5, 0.0, 0.0, 0.0, 0.0, 0.0};
    x.camera_offset_std = {0.5, 0.1, 0.1, 0.0, 0.0, 0.0};
    t.add(x);
  }
  MethodScores m("m", {"a", "b"});
  m.add_run(t);
  ScoringOptions opt;
  opt.converged_after_s = 5.0;
  const MethodSummary s = m.summary(opt);
  EXPECT_EQ(s.all.angle_coverage.estimated, 100u);  // joint b is not estimated
  EXPECT_EQ(s.all.angle_coverage.within, 51u);
  EXPECT_DOUBLE_EQ(s.all.angle_coverage.fraction(), 0.51);
  ASSERT_EQ(s.all.joint_angle_coverage.size(), 2u);
  EXPECT_TRUE(std::isnan(s.all.joint_angle_coverage[1].fraction()));  // not estimated: no 0%
  EXPECT_DOUBLE_EQ(s.all.bias_coverage.fraction(), 0.9);
  // Camera: 3 estimated components per sample, x always outside.
  EXPECT_EQ(s.all.camera_offset_coverage.estimated, 300u);
  EXPECT_DOUBLE_EQ(s.all.camera_offset_coverage.fraction(), 2.0 / 3.0);
  // Per axis: x never within, y and z always, the rotations not estimated;
  // the pooled share is their sum.
  EXPECT_EQ(s.all.camera_axis_coverage[0].estimated, 100u);
  EXPECT_DOUBLE_EQ(s.all.camera_axis_coverage[0].fraction(), 0.0);
  EXPECT_DOUBLE_EQ(s.all.camera_axis_coverage[1].fraction(), 1.0);
  EXPECT_DOUBLE_EQ(s.all.camera_axis_coverage[2].fraction(), 1.0);
  for (std::size_t k = 3; k < 6; ++k) EXPECT_EQ(s.all.camera_axis_coverage[k].estimated, 0u);
  EXPECT_EQ(s.converged.camera_axis_coverage[0].estimated, 50u);
  EXPECT_EQ(s.all.camera_translation_m.p50, 0.02);
  // From 5 s: angle errors 2.0 .. 3.96, of which only 2.0 is within.
  EXPECT_EQ(s.converged.angle_coverage.estimated, 50u);
  EXPECT_EQ(s.converged.angle_coverage.within, 1u);
  EXPECT_DOUBLE_EQ(s.converged.bias_coverage.fraction(), 1.0);
  // Without standard deviations (or truth) there is nothing to say.
  MethodScores bare("bare", {"a"});
  bare.add(0.0, {0.1, 0.1}, std::vector<double>{0.1}, std::vector<double>{0.1});
  const MethodSummary b = bare.summary(opt);
  EXPECT_EQ(b.all.angle_coverage.estimated, 0u);
  EXPECT_TRUE(std::isnan(b.all.angle_coverage.fraction()));
  EXPECT_TRUE(b.all.joint_angle_coverage.empty());
  EXPECT_EQ(b.all.camera_translation_m.count, 0u);
}

TEST(Scoring, EndEffectorConsistencyCountsEachPoseComponent) {
  // Two end effectors. Left: position errors 1, 0, 0 mm against sds 1 mm
  // (within), rotation 0.03 rad on x against 0.01 (outside). Right: position
  // x error 3 mm against 1 mm (outside) in the first 50 samples, 0 after;
  // rotation within.
  ErrorTrace t(0, 2);
  for (int i = 0; i < 100; ++i) {
    ScoredSample x;
    x.time_s = 0.1 * i;
    x.end_effectors = {{0.001, 0.03}, {i < 50 ? 0.003 : 0.0, 0.0}};
    x.end_effector_error = {0.001, 0, 0, 0.03, 0, 0, i < 50 ? 0.003 : 0.0, 0, 0, 0, 0, 0};
    x.end_effector_std = {0.001, 0.001, 0.001, 0.01, 0.01, 0.01,
                          0.001, 0.001, 0.001, 0.01, 0.01, 0.01};
    t.add(x);
  }
  MethodScores m("m", {}, {"left_ee", "right_ee"});
  m.add_run(t);
  ScoringOptions opt;
  opt.converged_after_s = 5.0;
  const MethodSummary s = m.summary(opt);
  // Both end effectors pooled: 600 position components, 50 outside.
  EXPECT_EQ(s.all.end_effector_position_coverage.estimated, 600u);
  EXPECT_EQ(s.all.end_effector_position_coverage.within, 550u);
  EXPECT_EQ(s.all.end_effector_rotation_coverage.within, 500u);  // left x never
  EXPECT_DOUBLE_EQ(s.converged.end_effector_position_coverage.fraction(), 1.0);
  // Each end effector alone.
  ASSERT_EQ(s.end_effectors.size(), 2u);
  EXPECT_DOUBLE_EQ(s.end_effectors[0].all.end_effector_position_coverage.fraction(), 1.0);
  EXPECT_DOUBLE_EQ(s.end_effectors[0].all.end_effector_rotation_coverage.fraction(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.end_effectors[1].all.end_effector_position_coverage.fraction(),
                   1.0 - 50.0 / 300.0);
  EXPECT_DOUBLE_EQ(s.end_effectors[1].all.end_effector_rotation_coverage.fraction(), 1.0);
  // Six values per end effector, in every sample or none.
  ScoredSample bad;
  bad.time_s = 20;
  bad.end_effectors = {{0, 0}, {0, 0}};
  bad.end_effector_error = {0, 0, 0, 0, 0, 0};
  bad.end_effector_std = {1, 1, 1, 1, 1, 1};
  expect_error_naming([&] { t.add(bad); },
                      "end-effector pose errors (6 per end effector) have 6 values, expected 12");
  bad.end_effector_error.clear();
  bad.end_effector_std.clear();
  expect_error_naming([&] { t.add(bad); }, "for every sample");
}

TEST(Scoring, CameraOffsetOfInvertsTheVirtualJoints) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (int trial = 0; trial < 20; ++trial) {
    CameraOffset o;
    for (int k = 0; k < 6; ++k) o[k] = u(rng);
    // robot_model.h: T = Trans(x, y, z) Rx(roll) Ry(pitch) Rz(yaw).
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = o.head<3>();
    T.linear() = (Eigen::AngleAxisd(o[3], Eigen::Vector3d::UnitX()) *
                  Eigen::AngleAxisd(o[4], Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(o[5], Eigen::Vector3d::UnitZ()))
                     .toRotationMatrix();
    EXPECT_LT((camera_offset_of(T) - o).cwiseAbs().maxCoeff(), 1e-12) << o.transpose();
  }
}

TEST(Scoring, CameraPosesFollowTheModelsVirtualJoints) {
  const auto model = std::make_shared<const RobotModel>(
      RobotModel::from_urdf_string(test::kRobotUrdf, ".", RobotModelOptions{}));
  CameraPoses poses(model);
  const int n = model->num_joints() - 6;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  Eigen::VectorXd angles(n);
  for (int j = 0; j < n; ++j) angles[j] = u(rng);
  // The nominal camera at these angles: no offset.
  KinematicsState state(*model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model->num_joints());
  q.head(n) = angles;
  forward_kinematics(*model, q, state);
  const Eigen::Isometry3d nominal = state.T_root_link[model->nominal_camera_link()];
  EXPECT_TRUE(poses.camera(angles, CameraOffset::Zero()).isApprox(nominal, 1e-14));
  // A known offset: 2 cm along the camera's x and 1 degree about its z.
  CameraOffset known = CameraOffset::Zero();
  known[0] = 0.02;
  known[5] = M_PI / 180;
  const Eigen::Isometry3d moved = poses.camera(angles, known);
  const PoseError e = pose_error(moved, nominal);
  EXPECT_NEAR(e.translation_m, 0.02, 1e-12);
  EXPECT_NEAR(e.rotation_rad, M_PI / 180, 1e-12);
  EXPECT_NEAR((nominal.inverse() * moved).translation().x(), 0.02, 1e-12);
  // offset_to finds the offset that reaches a pose, and camera() goes back.
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::Isometry3d target = nominal;
    target.translation() += Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1;
    target.linear() =
        target.linear() * Eigen::AngleAxisd(u(rng), Eigen::Vector3d(u(rng), u(rng), 1).normalized())
                              .toRotationMatrix();
    const CameraOffset o = poses.offset_to(angles, target);
    EXPECT_TRUE(poses.camera(angles, o).isApprox(target, 1e-12));
  }
  // A model without virtual joints cannot be used.
  RobotModelOptions plain;
  plain.add_virtual_camera_joints = false;
  EXPECT_THROW(CameraPoses(std::make_shared<const RobotModel>(
                   RobotModel::from_urdf_string(test::kRobotUrdf, ".", plain))),
               InputError);
}

TEST(Scoring, BadInputIsNamed) {
  ErrorTrace t(2);
  t.add(1.0, {0.1, 0.1});
  expect_error_naming([&] { t.add(0.5, {0.1, 0.1}); }, "earlier");
  expect_error_naming(
      [&] {
        t.add(2.0, {0.1, 0.1}, std::vector<double>{0.1, 0.2});
      },
      "every sample");
  expect_error_naming([&] { t.add(2.0, {0.1, 0.1}, std::vector<double>{0.1}); }, "expected 2");
  MethodScores m("fusion", {"a"}), ref("encoders", {"a"});
  m.add(0.0, {0.1, 0.1});
  ScoringOptions opt;
  opt.convergence_threshold_m = 0.0;
  expect_error_naming([&] { m.summary(opt); }, "convergence_threshold_m");
  expect_error_naming([&] { m.summary(ScoringOptions{}, &ref); }, "runs");
  expect_error_naming([&] { m.merge(MethodScores("fusion", {"b"})); }, "different joints");
  opt = ScoringOptions{};
  opt.lost_threshold_m = 0.0;
  expect_error_naming([&] { m.summary(opt); }, "lost_threshold_m");
  opt = ScoringOptions{};
  opt.lost_after_s = -1.0;
  expect_error_naming([&] { m.summary(opt); }, "lost_after_s");
  ErrorTrace two(0, 2);
  expect_error_naming([&] { two.add(0.0, {0.1, 0.1}); }, "expected 2");
  ScoredSample x;
  x.end_effectors = {{0.1, 0.1}};
  x.camera_offset_std = {0.1, 0.1};
  expect_error_naming([&] { ErrorTrace().add(x); }, "camera offset values have 2");
  x.camera_offset_std = {};
  ErrorTrace with_camera;
  x.camera = PoseError{0.1, 0.1};
  with_camera.add(x);
  x.camera.reset();
  expect_error_naming([&] { with_camera.add(x); }, "every sample");
}

}  // namespace
}  // namespace arttrack::sim
