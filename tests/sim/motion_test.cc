#include "arttrack/sim/motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../expect_error.h"
#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

using test_support::expect_error_naming;

// Three joints: a shoulder with wide limits, an elbow whose home sits on its
// lower limit, and a wrist with a narrow range.
JointTrajectory make_trajectory() {
  return JointTrajectory({"shoulder", "elbow", "wrist"}, {0.1, 0.0, 0.2},
                         {{-2.0, 2.0}, {0.0, 2.5}, {0.0, 0.3}});
}

TEST(Motion, NoPartsHoldsHome) {
  const JointTrajectory traj = make_trajectory();
  for (double t : {0.0, 1.0, 100.0}) {
    EXPECT_EQ(traj.position(t), (std::vector<double>{0.1, 0.0, 0.2}));
    EXPECT_EQ(traj.velocity(t), (std::vector<double>{0.0, 0.0, 0.0}));
  }
}

TEST(Motion, SinusoidMatchesClosedForm) {
  JointTrajectory traj = make_trajectory();
  SinusoidMotion s;
  s.joints = {"shoulder", "elbow"};
  s.amplitude_rad = 0.4;
  s.frequency_hz = 0.3;
  s.phase_rad = 0.7;
  s.centre_rad = {0.5, 1.0};
  traj.add(s);
  const double omega = 2 * std::numbers::pi * 0.3;
  for (double t = 0.0; t < 20.0; t += 0.137) {
    const std::vector<double> q = traj.position(t), qd = traj.velocity(t);
    EXPECT_NEAR(q[0], 0.5 + 0.4 * std::sin(omega * t + 0.7), 1e-12);
    EXPECT_NEAR(q[1], 1.0 + 0.4 * std::sin(omega * t + 0.7), 1e-12);
    EXPECT_EQ(q[2], 0.2);
    EXPECT_NEAR(qd[0], 0.4 * omega * std::cos(omega * t + 0.7), 1e-12);
    EXPECT_NEAR(qd[1], qd[0], 1e-12);
    EXPECT_EQ(qd[2], 0.0);
  }
}

TEST(Motion, SinusoidDefaultCentreIsHomeAndFadeInStartsAtHome) {
  JointTrajectory traj = make_trajectory();
  SinusoidMotion s;
  s.joints = {"shoulder"};
  s.amplitude_rad = 0.3;
  s.frequency_hz = 0.5;
  s.phase_rad = std::numbers::pi / 2;  // would start at the crest without the fade
  s.fade_in_s = 2.0;
  traj.add(s);
  EXPECT_EQ(traj.position(0.0)[0], 0.1);
  EXPECT_EQ(traj.velocity(0.0)[0], 0.0);
  for (double t = 2.0; t < 10.0; t += 0.25)
    EXPECT_NEAR(traj.position(t)[0],
                0.1 + 0.3 * std::sin(std::numbers::pi * t + std::numbers::pi / 2), 1e-12);
}

TEST(Motion, WaypointsAreHitExactlyAndHeld) {
  JointTrajectory traj = make_trajectory();
  WaypointMotion w;
  w.joints = {"elbow", "shoulder"};
  w.times_s = {1.0, 2.5, 4.0};
  w.positions_rad = {{0.5, -1.0}, {2.0, 1.5}, {1.0, 0.3}};
  traj.add(w);
  for (std::size_t k = 0; k < w.times_s.size(); ++k) {
    const std::vector<double> q = traj.position(w.times_s[k]);
    EXPECT_EQ(q[1], w.positions_rad[k][0]);
    EXPECT_EQ(q[0], w.positions_rad[k][1]);
    // Rest-to-rest: zero velocity at every waypoint.
    EXPECT_EQ(traj.velocity(w.times_s[k])[0], 0.0);
  }
  EXPECT_EQ(traj.position(0.0)[1], 0.5);  // first held before
  EXPECT_EQ(traj.position(9.0)[1], 1.0);  // last held after
  // Minimum jerk halfway through a segment is the midpoint with peak speed
  // 15/8 (dq / dt).
  EXPECT_NEAR(traj.position(1.75)[1], 1.25, 1e-12);
  EXPECT_NEAR(traj.velocity(1.75)[1], 15.0 / 8.0 * 1.5 / 1.5, 1e-12);
  // Monotone between waypoints: no overshoot.
  for (double t = 1.0; t <= 2.5; t += 0.01) {
    const double q = traj.position(t)[1];
    EXPECT_GE(q, 0.5 - 1e-12);
    EXPECT_LE(q, 2.0 + 1e-12);
  }
}

TEST(Motion, OutOfViewLeavesAndComesBack) {
  JointTrajectory traj = make_trajectory();
  OutOfViewMotion o;
  o.joints = {"shoulder", "elbow"};
  o.out_of_view_rad = {1.8, 2.2};
  o.leave_s = 3.0;
  o.return_s = 10.0;
  o.move_duration_s = 1.5;
  traj.add(o);
  const std::vector<double> home = traj.home_rad();
  for (double t : {0.0, 3.0, 11.5, 20.0}) {
    EXPECT_EQ(traj.position(t)[0], home[0]) << t;
    EXPECT_EQ(traj.position(t)[1], home[1]) << t;
  }
  for (double t : {4.5, 7.0, 10.0}) {
    EXPECT_EQ(traj.position(t)[0], 1.8) << t;
    EXPECT_EQ(traj.position(t)[1], 2.2) << t;
  }
  EXPECT_GT(traj.position(3.75)[0], home[0]);
  EXPECT_LT(traj.position(3.75)[0], 1.8);
}

TEST(Motion, PartsOnOneJointAdd) {
  JointTrajectory traj = make_trajectory();
  OutOfViewMotion o;
  o.joints = {"shoulder"};
  o.out_of_view_rad = {1.0};
  o.leave_s = 1.0;
  o.return_s = 5.0;
  o.move_duration_s = 1.0;
  SinusoidMotion s;
  s.joints = {"shoulder"};
  s.amplitude_rad = 0.2;
  s.frequency_hz = 1.0;
  traj.add(o);
  traj.add(s);
  // At 3 s: out-of-view angle plus the sinusoid's displacement about home.
  EXPECT_NEAR(traj.position(3.25)[0], 1.0 + 0.2 * std::sin(2 * std::numbers::pi * 3.25), 1e-12);
}

TEST(Motion, LimitsClampAndStopTheVelocity) {
  JointTrajectory traj = make_trajectory();
  SinusoidMotion s;
  s.joints = {"shoulder", "elbow", "wrist"};
  s.amplitude_rad = 3.0;
  s.frequency_hz = 0.7;
  traj.add(s);
  int clamped = 0;
  // From 1 ms on: at t = 0 the elbow starts exactly on its limit, unclamped.
  for (double t = 0.001; t < 10.0; t += 0.001) {
    const std::vector<double> q = traj.position(t), qd = traj.velocity(t);
    for (std::size_t j = 0; j < 3; ++j) {
      const JointLimit& lim = traj.limits()[j];
      EXPECT_GE(q[j], lim.lower_rad);
      EXPECT_LE(q[j], lim.upper_rad);
      if (q[j] == lim.lower_rad || q[j] == lim.upper_rad) {
        EXPECT_EQ(qd[j], 0.0);
        ++clamped;
      }
    }
  }
  EXPECT_GT(clamped, 1000);
}

RandomMotion random_part(double speed_scale) {
  RandomMotion r;
  r.joints = {"shoulder", "elbow", "wrist"};
  r.amplitude_rad = 0.5;
  r.speed_scale = speed_scale;
  r.margin_rad = 0.05;
  r.fade_in_s = 1.0;
  return r;
}

TEST(Motion, RandomIsDeterministicFromSeed) {
  JointTrajectory a = make_trajectory(), b = make_trajectory(), c = make_trajectory();
  std::mt19937_64 rng_a(42), rng_b(42), rng_c(43);
  a.add(random_part(1.0), rng_a);
  b.add(random_part(1.0), rng_b);
  c.add(random_part(1.0), rng_c);
  double max_diff = 0.0;
  for (double t = 0.0; t < 30.0; t += 0.1) {
    EXPECT_EQ(a.position(t), b.position(t));
    EXPECT_EQ(a.velocity(t), b.velocity(t));
    max_diff = std::max(max_diff, std::abs(a.position(t)[0] - c.position(t)[0]));
  }
  EXPECT_GT(max_diff, 0.05);  // another seed, another motion
}

TEST(Motion, RandomStaysInsideLimitsWithMarginAndStartsAtHome) {
  for (double scale : {1.0, 3.0}) {
    JointTrajectory traj = make_trajectory();
    std::mt19937_64 rng(7);
    traj.add(random_part(scale), rng);
    EXPECT_EQ(traj.position(0.0), traj.home_rad());
    std::vector<double> lo(3, 1e9), hi(3, -1e9);
    for (double t = 1.0; t < 300.0; t += 0.01) {
      const std::vector<double> q = traj.position(t);
      for (std::size_t j = 0; j < 3; ++j) {
        EXPECT_GE(q[j], traj.limits()[j].lower_rad + 0.05 - 1e-12) << j << " " << t;
        EXPECT_LE(q[j], traj.limits()[j].upper_rad - 0.05 + 1e-12) << j << " " << t;
        lo[j] = std::min(lo[j], q[j]);
        hi[j] = std::max(hi[j], q[j]);
      }
    }
    // Every joint really moves, the narrow wrist within its 0.2 rad room.
    for (std::size_t j = 0; j < 3; ++j) EXPECT_GT(hi[j] - lo[j], 0.1) << j;
    EXPECT_LE(hi[0] - lo[0], 1.0 + 1e-12);  // +- amplitude
  }
}

TEST(Motion, RandomRmsSpeedFollowsSpeedScale) {
  for (double scale : {1.0, 3.0}) {
    JointTrajectory traj = make_trajectory();
    std::mt19937_64 rng(11);
    traj.add(random_part(scale), rng);
    // The shoulder has room for the full amplitude, so its RMS speed over a
    // long run is scale * 0.2 rad/s (cross terms of different frequencies
    // average out).
    double sum2 = 0.0;
    int n = 0;
    for (double t = 1.0; t < 3000.0; t += 0.01, ++n) sum2 += std::pow(traj.velocity(t)[0], 2);
    EXPECT_NEAR(std::sqrt(sum2 / n), 0.2 * scale, 0.03 * scale);
  }
}

TEST(Motion, ContinuousAtOneMillisecondAndVelocityIsTheDerivative) {
  JointTrajectory traj = make_trajectory();
  std::mt19937_64 rng(3);
  traj.add(random_part(3.0), rng);
  OutOfViewMotion o;
  o.joints = {"shoulder"};
  o.out_of_view_rad = {1.5};
  o.leave_s = 4.0;
  o.return_s = 8.0;
  o.move_duration_s = 1.0;
  traj.add(o);
  SinusoidMotion s;
  s.joints = {"elbow"};
  s.amplitude_rad = 0.3;
  s.frequency_hz = 0.5;
  s.centre_rad = {0.6};
  s.fade_in_s = 2.0;
  traj.add(s);
  // Bound on any joint's speed, the sum of the parts' bounds: random motion
  // <= V sqrt(2 K) = 1.7 rad/s plus its fade-in 15/8 * 1.05 = 2.0, the
  // out-of-view move 15/8 * 1.4 = 2.6, the sinusoid 0.3 pi = 0.94 plus its
  // fade-in 15/16 * 0.9 = 0.85.
  const double dt = 1e-3, max_speed = 8.0;
  std::vector<double> prev = traj.position(0.0);
  for (double t = dt; t < 15.0; t += dt) {
    const std::vector<double> q = traj.position(t);
    const std::vector<double> qd = traj.velocity(t);
    const std::vector<double> qp = traj.position(t + 1e-6), qm = traj.position(t - 1e-6);
    for (std::size_t j = 0; j < 3; ++j) {
      EXPECT_LE(std::abs(q[j] - prev[j]), max_speed * dt) << j << " " << t;
      const bool at_limit =
          q[j] == traj.limits()[j].lower_rad || q[j] == traj.limits()[j].upper_rad;
      if (!at_limit) {
        EXPECT_NEAR(qd[j], (qp[j] - qm[j]) / 2e-6, 1e-5) << j << " " << t;
      }
    }
    prev = q;
  }
}

TEST(Motion, BadInputNamesTheField) {
  JointTrajectory traj = make_trajectory();
  SinusoidMotion s;
  s.joints = {"shoulder"};
  s.frequency_hz = 0.0;
  expect_error_naming([&] { traj.add(s); }, "frequency_hz");
  s.frequency_hz = 1.0;
  s.joints = {"knee"};
  expect_error_naming([&] { traj.add(s); }, "knee");
  s.joints = {"shoulder", "shoulder"};
  expect_error_naming([&] { traj.add(s); }, "twice");
  WaypointMotion w;
  w.joints = {"wrist"};
  w.times_s = {1.0, 1.0};
  w.positions_rad = {{0.1}, {0.2}};
  expect_error_naming([&] { traj.add(w); }, "times_s");
  w.times_s = {1.0, 2.0};
  w.positions_rad = {{0.1}, {0.5}};  // wrist upper limit is 0.3
  expect_error_naming([&] { traj.add(w); }, "positions_rad[1]");
  RandomMotion r = random_part(1.0);
  r.speed_scale = -1.0;
  std::mt19937_64 rng(1);
  expect_error_naming([&] { traj.add(r, rng); }, "speed_scale");
  OutOfViewMotion o;
  o.joints = {"shoulder"};
  o.out_of_view_rad = {1.0};
  o.leave_s = 5.0;
  o.return_s = 6.0;
  o.move_duration_s = 2.0;
  expect_error_naming([&] { traj.add(o); }, "return_s");
  expect_error_naming([] { JointTrajectory({"a"}, {1.0}, {{-0.5, 0.5}}); }, "home");
  expect_error_naming([&] { traj.joint_index("nope"); }, "nope");
}

}  // namespace
}  // namespace arttrack::sim
