// Acquisition (tracker/internal): the annealed searches of the first image
// and the re-acquisitions the health check calls for.
#include "arttrack/tracker/internal/acquisition.h"

#include <gtest/gtest.h>

#include <cmath>

#include "health_check.h"
#include "planar_arm.h"

namespace arttrack {
namespace {

using namespace test_support;  // the planar arm (planar_arm.h)

constexpr double kTrueShoulder = 0.4, kTrueElbow = -0.6;
constexpr double kBias = 0.25;  // rad, on both encoders (14 degrees)

// The arm at the truth in front of a wall at 2 m, so that an estimate off
// the arm is contradicted (the camera sees the wall behind it).
DepthImage arm_before_wall(const RobotModel& model) {
  DepthImage image = render_truth(model, kTrueShoulder, kTrueElbow);
  for (float& z : image.depth_m)
    if (z == 0) z = 2.0f;
  return image;
}

struct Fixture {
  explicit Fixture(TrackerConfig config = small_config(TrackingMethod::kFullFusion))
      : setup(arm_model(), config, {"shoulder", "elbow"}),
        image(setup),
        acquisition(setup),
        check(*setup.model, setup.n_phys, setup.config.health,
              setup.config.depth_model.max_range_m),
        health(check.initial_health()),
        observed(arm_before_wall(*setup.model)) {
    reading.assign(std::size_t(setup.n_phys), 0.0);
    reading[std::size_t(shoulder())] = kTrueShoulder + kBias;
    reading[std::size_t(elbow())] = kTrueElbow + kBias;
    belief = initial_joint_belief(*setup.filter_model, reading);
    encoders_arm = belief.mean_a;
    if (image.set_image(observed, kCamera)) acquisition.draw(image.geometry());
  }
  int shoulder() const { return setup.model->joint_index("shoulder"); }
  int elbow() const { return setup.model->joint_index("elbow"); }
  std::vector<double> prior_std() const {
    std::vector<double> sd;
    for (double v : belief.var_a) sd.push_back(std::sqrt(v));
    return sd;
  }

  TrackerSetup setup;
  ImageFilter image;
  Acquisition acquisition;
  HealthCheck check;
  TrackingHealth health;
  DepthImage observed;
  std::vector<double> reading;  // DOF order
  JointBelief belief;
  std::vector<double> encoders_arm;  // every DOF: the readings, the camera at 0
};

TEST(Acquisition, SearchesTheEstimatedBiasesThenTheCameraWithAnnealedNoise) {
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  c.acquisition.passes = 4;
  const TrackerSetup setup(arm_model(), c, {"shoulder", "elbow"});
  const AcquisitionSetup s(setup);
  ASSERT_TRUE(s.on);
  ASSERT_EQ(s.blocks.size(), 8u);
  EXPECT_EQ(s.blocks[0].name, "shoulder");  // root to hand
  EXPECT_EQ(s.blocks[1].name, "elbow");
  EXPECT_EQ(s.blocks[2].name, "camera_offset_x");
  ASSERT_EQ(s.pass_models.size(), 3u);
  const double coarse = c.acquisition.coarse_noise_std_m, fine = c.depth_model.noise_std_m;
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(s.pass_models[std::size_t(k)].noise_std_m,
                coarse * std::pow(fine / coarse, k / 3.0), 1e-15);
  EXPECT_DOUBLE_EQ(s.reopened_bias_var_rad2,
                   c.acquisition.bias_std_rad * c.acquisition.bias_std_rad);

  c.acquisition.passes = 1;
  EXPECT_FALSE(AcquisitionSetup(TrackerSetup(arm_model(), c, {"shoulder", "elbow"})).on);
  c = small_config(TrackingMethod::kCameraOffsetOnly);
  EXPECT_FALSE(AcquisitionSetup(TrackerSetup(arm_model(), c, {"shoulder", "elbow"})).on);
}

// From encoders 14 degrees off, the first image's search finds the arm,
// with the camera joints searched or held at their prior (the default): in
// 18 of 20 seeds each way (measured), both joints within 1.5 degrees. One
// seed is a lucky draw either way (seed 1 fails held, seed 12 searched).
TEST(Acquisition, FirstImageFindsTheArmTheBiasedEncodersMiss) {
  for (const bool search_camera : {false, true}) {
    SCOPED_TRACE(search_camera ? "camera searched" : "camera held");
    int found = 0;
    for (unsigned long long seed = 1; seed <= 20; ++seed) {
      TrackerConfig c = small_config(TrackingMethod::kFullFusion);
      c.seed = seed;
      c.acquisition.search_camera = search_camera;
      Fixture f(c);
      f.acquisition.acquire_first(f.image, f.observed, f.prior_std(), 0.0, f.belief, f.health);
      const auto near = [](double a, double b) { return std::abs(a - b) < 1.5 * kRadPerDeg; };
      if (near(f.belief.mean_a[std::size_t(f.shoulder())], kTrueShoulder) &&
          near(f.belief.mean_a[std::size_t(f.elbow())], kTrueElbow) &&
          near(f.belief.mean_b[std::size_t(f.shoulder())], kBias))
        ++found;
      EXPECT_EQ(f.health.acquisitions, 1);
      EXPECT_EQ(f.acquisition.workspace().last_search_s, 0.0);
    }
    EXPECT_GE(found, 17);
  }
}

TEST(Acquisition, TheHealthChecksCountsAndThePeriodDecideTheSearch) {
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  c.acquisition.period_s = 1.0;
  Fixture f(c);
  EXPECT_EQ(f.acquisition.due_search(f.check, 0.0), SearchKind::kPeriodic);  // never searched
  f.acquisition.acquire_first(f.image, f.observed, f.prior_std(), 0.0, f.belief, f.health);
  EXPECT_EQ(f.acquisition.due_search(f.check, 0.5), SearchKind::kNone);
  EXPECT_EQ(f.acquisition.due_search(f.check, 1.0), SearchKind::kPeriodic);
  // The encoders' arm, 14 degrees off, against the image: poor after
  // lost_after_images images in a row.
  for (int k = 0; k < c.health.lost_after_images; ++k) {
    EXPECT_EQ(f.acquisition.due_search(f.check, 0.5), SearchKind::kNone);
    f.check.update(f.encoders_arm, f.observed, 0.1 * k, f.image.geometry().renderer(), f.health);
  }
  EXPECT_EQ(f.acquisition.due_search(f.check, 0.5), SearchKind::kPoor);
}

// A chain the health check found poor takes the search's result when the
// image prefers it by the margin, and keeps its belief otherwise.
TEST(Acquisition, ReacquisitionMovesAPoorChainOnlyWhenTheImagePrefersTheResult) {
  for (const double margin : {5.0, 1e6}) {
    TrackerConfig c = small_config(TrackingMethod::kFullFusion);
    c.acquisition.accept_margin_nats = margin;
    Fixture f(c);
    for (int k = 0; k < c.health.lost_after_images; ++k)
      f.check.update(f.encoders_arm, f.observed, 0.1 * k, f.image.geometry().renderer(), f.health);
    ASSERT_TRUE(f.check.chain_poor(0));
    const JointBelief before = f.belief;
    std::vector<char> reopened(std::size_t(f.setup.n), 0);
    f.acquisition.reacquire(SearchKind::kPoor, f.image, f.observed, f.check, f.reading, 0.5,
                            f.belief, f.health, reopened);
    EXPECT_EQ(f.health.acquisitions, 1);
    EXPECT_EQ(f.check.failed_reacquisitions(), 1);
    if (margin > 1e5) {
      EXPECT_EQ(f.belief.mean_a, before.mean_a);
      EXPECT_EQ(f.health.chains_reacquired, 0);
      EXPECT_EQ(reopened, std::vector<char>(std::size_t(f.setup.n), 0));
      continue;
    }
    EXPECT_EQ(f.health.chains_reacquired, 1);
    EXPECT_NEAR(f.belief.mean_a[std::size_t(f.shoulder())], kTrueShoulder, 1.5 * kRadPerDeg);
    EXPECT_NEAR(f.belief.mean_a[std::size_t(f.elbow())], kTrueElbow, 1.5 * kRadPerDeg);
    EXPECT_EQ(reopened[std::size_t(f.shoulder())], 1);
    EXPECT_EQ(reopened[std::size_t(f.elbow())], 1);
    EXPECT_EQ(reopened[std::size_t(f.setup.n_phys)], 0);  // the camera is not re-opened
  }
}

}  // namespace
}  // namespace arttrack
