// The shipped tracker configuration is robot-agnostic and built into the
// library: it is the file tracker/config/default.yaml, and a tracker built
// from it runs every method on a robot that is not the project's dual-arm
// one (tests/tracker/data/single_arm.urdf).
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "../error_of.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/tracker.h"
#include "arttrack/tracker/tracker_config_yaml.h"
#include "arttrack/tracker/units.h"

namespace arttrack {
namespace {

using arttrack::test_support::error_of;

const std::string kUrdf = std::string(ARTTRACK_SOURCE_DIR) + "/tests/tracker/data/single_arm.urdf";

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(DefaultConfigTest, BuiltInTextIsTheShippedFile) {
  EXPECT_EQ(default_tracker_config_yaml(),
            read_text(std::string(ARTTRACK_SOURCE_DIR) + "/tracker/config/default.yaml"));
  const TrackerConfig c = default_tracker_config();
  EXPECT_EQ(c.source, kDefaultTrackerConfigName);
  EXPECT_TRUE(c.joint_overrides.empty());
  EXPECT_TRUE(c.end_effectors.empty());
}

TEST(DefaultConfigTest, EveryMethodRunsOnAnotherRobot) {
  const auto model = std::make_shared<const RobotModel>(RobotModel::from_urdf_file(kUrdf));
  const std::vector<std::string> joints{"yaw", "pitch_1", "pitch_2"};
  // The true configuration's depth image, at a small camera.
  const CameraIntrinsics camera = CameraIntrinsics::from_vertical_fov(80, 60, 60 * kRadPerDeg);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model->num_joints());
  q[model->joint_index("pitch_1")] = 0.3;
  q[model->joint_index("pitch_2")] = -0.5;
  KinematicsState state(*model);
  forward_kinematics(*model, q, state);
  DepthRenderer renderer(*model, camera);
  DepthImage image;
  renderer.render(state, image);

  for (const std::string& method : all_method_names()) {
    SCOPED_TRACE(method);
    TrackerConfig c = default_tracker_config();
    c.method = parse_method(method, "test");
    c.end_effectors = {"tool"};
    c.threads = 1;
    Tracker tracker(model, c,
                    c.method == TrackingMethod::kVisionOnly ? std::vector<std::string>{} : joints);
    const std::vector<double> reading{0.0, 0.3 + 2 * kRadPerDeg, -0.5};
    for (int k = 0; k <= 100; ++k) {
      if (c.method != TrackingMethod::kVisionOnly)
        tracker.add_joint_measurement(0.001 * k, reading);
      if (k == 50) tracker.add_depth_image(0.05, image, camera);
    }
    const TrackerEstimate e = tracker.estimate();
    EXPECT_EQ(e.joint_names, joints);
    ASSERT_EQ(e.T_camera_ee.size(), 1u);
    EXPECT_TRUE(e.T_camera_ee[0].matrix().allFinite());
    if (c.method == TrackingMethod::kFullFusion || c.method == TrackingMethod::kCameraOffsetOnly) {
      EXPECT_EQ(tracker.stats().images_applied, 1);
    }
  }
  // No end effector is fine: none is reported.
  Tracker plain(model, default_tracker_config(), joints);
  plain.add_joint_measurement(0, std::vector<double>{0, 0, 0});
  EXPECT_TRUE(plain.estimate().T_camera_ee.empty());
}

// What the dual-arm robot's overrides (now in its scene) do to any other
// robot: an error naming the joint, not a default that silently fits one.
TEST(DefaultConfigTest, OverrideOfAnotherRobotsJointIsAnError) {
  const auto model = std::make_shared<const RobotModel>(RobotModel::from_urdf_file(kUrdf));
  YamlDocument doc = default_tracker_document();
  apply_override(doc, "joints.per_joint.head_pan_joint.estimate_bias=false");
  const TrackerConfig c = tracker_config_from_yaml(doc);
  const std::string e = error_of([&] { Tracker(model, c, {"yaw", "pitch_1", "pitch_2"}); });
  EXPECT_NE(e.find("unknown joint 'head_pan_joint'"), std::string::npos) << e;
}

}  // namespace
}  // namespace arttrack
