// CameraCarrierMotion (tracker/internal): the camera offset's random walk
// with the joints that carry the camera, against its closed form.
#include "arttrack/tracker/internal/camera_carrier_motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "../error_of.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "planar_arm.h"

namespace arttrack {
namespace {

std::vector<std::string> physical_joints(const RobotModel& model) {
  std::vector<std::string> names;
  for (int dof = 0; dof < model.num_joints(); ++dof)
    if (!model.is_virtual_joint(dof)) names.push_back(model.joint_name(dof));
  return names;
}

std::shared_ptr<const RobotModel> dual_arm() {
  return std::make_shared<const RobotModel>(
      RobotModel::from_urdf_file(std::string(ARTTRACK_SOURCE_DIR) + "/models/dual_arm.urdf"));
}

// The dual arm's camera sits on its head: the two neck joints carry it and
// no arm joint does. A turn of the neck grows the six virtual joints'
// variances by sigma_m^2 times the turn less sqrt(2) sigma_q, translation
// and rotation each by its own sigma_m; nothing else grows.
TEST(CameraCarrierMotion, TheHeadsTurnLessEncoderNoiseGrowsTheCameraOffset) {
  const auto model = dual_arm();
  TrackerConfig config;
  config.camera_translation.motion_diffusion_per_sqrt_rad = 0.002;
  config.camera_rotation.motion_diffusion_per_sqrt_rad = 0.01;
  const TrackerSetup setup(model, config, physical_joints(*model));
  CameraCarrierMotion motion(*model, *setup.filter_model, config);
  const int pan = model->joint_index("head_pan_joint"),
            tilt = model->joint_index("head_tilt_joint");
  ASSERT_TRUE(motion.on());
  EXPECT_EQ(motion.carrying_dofs(), (std::vector<int>{pan, tilt}));

  std::vector<double> q(std::size_t(model->num_joints()), 0.1), added(q.size(), -1.0);
  EXPECT_EQ(motion.added_variance(q, added), 0.0);  // the first image counts no travel
  for (double v : added) EXPECT_EQ(v, 0.0);

  const double allowance = std::sqrt(2.0) * config.joint_defaults.encoder_noise_rad;
  q[std::size_t(pan)] += 0.05;                                    // the pan turns 0.05 rad
  q[std::size_t(tilt)] -= 0.5 * allowance;                        // the tilt within its noise
  q[std::size_t(model->joint_index("left_arm_joint_1"))] += 1.0;  // an arm: carries nothing
  const double travel = motion.added_variance(q, added);
  EXPECT_NEAR(travel, 0.05 - allowance, 1e-15);
  // The six virtual joints come last: x, y, z, then the three rotations.
  const int first_rotation = model->num_joints() - 3;
  for (int dof = 0; dof < model->num_joints(); ++dof) {
    const double expected = !model->is_virtual_joint(dof) ? 0.0
                            : dof < first_rotation        ? 0.002 * 0.002 * travel
                                                          : 0.01 * 0.01 * travel;
    EXPECT_NEAR(added[std::size_t(dof)], expected, 1e-18) << model->joint_name(dof);
  }
  // Standing still adds nothing.
  EXPECT_EQ(motion.added_variance(q, added), 0.0);
  EXPECT_EQ(added[std::size_t(model->num_joints() - 1)], 0.0);
}

// A camera fixed to the robot's base (the planar arm's) is carried by no
// joint, a sigma_m of 0 grows nothing, and vision only has no encoder to
// measure the travel: all three are off.
TEST(CameraCarrierMotion, AFixedCameraOrNoDiffusionIsOff) {
  const auto arm = test_support::arm_model();
  TrackerConfig config = test_support::small_config(TrackingMethod::kFullFusion);
  config.camera_rotation.motion_diffusion_per_sqrt_rad = 0.01;
  const TrackerSetup fixed(arm, config, {"shoulder", "elbow"});
  const CameraCarrierMotion on_base(*arm, *fixed.filter_model, config);
  EXPECT_FALSE(on_base.on());
  EXPECT_TRUE(on_base.carrying_dofs().empty());

  const auto model = dual_arm();
  TrackerConfig none;
  none.camera_translation.motion_diffusion_per_sqrt_rad = 0;
  none.camera_rotation.motion_diffusion_per_sqrt_rad = 0;
  const TrackerSetup setup(model, none, physical_joints(*model));
  EXPECT_FALSE(CameraCarrierMotion(*model, *setup.filter_model, none).on());
  // Vision only: no encoder measures the head's travel apart from the images.
  TrackerConfig vision;
  vision.method = TrackingMethod::kVisionOnly;
  const TrackerSetup vision_setup(model, vision, physical_joints(*model));
  EXPECT_FALSE(CameraCarrierMotion(*model, *vision_setup.filter_model, vision).on());
}

TEST(CameraCarrierMotion, SizesAreChecked) {
  const auto model = dual_arm();
  const TrackerConfig config;
  const TrackerSetup setup(model, config, physical_joints(*model));
  CameraCarrierMotion motion(*model, *setup.filter_model, config);
  std::vector<double> q(std::size_t(model->num_joints()), 0.0), added(3, 0.0);
  EXPECT_EQ(test_support::error_of([&] { motion.added_variance(q, added); }),
            "camera carrier motion: expected " + std::to_string(model->num_joints()) +
                " DOFs, got " + std::to_string(model->num_joints()) + " and 3");
}

}  // namespace
}  // namespace arttrack
