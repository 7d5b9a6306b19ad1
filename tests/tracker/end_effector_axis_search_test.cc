// EndEffectorAxisSearch (end_effector_axis_search.h): a hand whose wrist is
// longer than the model's, seen from the side, found along its own axis;
// nothing moved when the hand matches its model, with or without a plate
// in front of it.
#include "arttrack/tracker/internal/end_effector_axis_search.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <string>

#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/units.h"

namespace arttrack {
namespace {

// A hand (a box 12 cm long along its link's z) on a wrist 0.3 m above a
// base, seen from the side by a camera 0.4 m away along the base's x: its
// side face is all the camera sees of it, and sliding along its length
// changes no depth there. `wrist_z` places the hand's joint.
std::string hand_urdf(double wrist_z) {
  return R"(<robot name="hand">
  <link name="base_link"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <link name="hand"><visual><origin xyz="0 0 0.06"/><geometry><box size="0.04 0.06 0.12"/></geometry></visual></link>
  <link name="camera_optical_frame"/>
  <joint name="wrist" type="revolute"><parent link="base_link"/><child link="hand"/>
    <origin xyz="0 0 )" +
         std::to_string(wrist_z) +
         R"("/><axis xyz="1 0 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="camera_joint" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="0.4 0 0.36" rpy="-1.5707963267948966 0 1.5707963267948966"/></joint>
</robot>)";
}

const CameraIntrinsics kCamera160x120 =
    CameraIntrinsics::from_vertical_fov(160, 120, 60 * kRadPerDeg);

DepthImage render(const RobotModel& model) {
  KinematicsState state(model);
  forward_kinematics(model, Eigen::VectorXd::Zero(model.num_joints()), state);
  DepthRenderer renderer(model, kCamera160x120);
  DepthImage image;
  renderer.render(state, image);
  return image;
}

struct Searched {
  Eigen::Vector3d shift_m;
  Eigen::Vector3d hand_axis;  // the hand's z in camera axes
  int accepted = 0;
};

// The search on `observed` from the nominal model at the zero
// configuration, with a rigid fit that moves nothing and knows the hand's
// position to 0.1 mm across its axis and 1.5 mm along it.
Searched search(const DepthImage& observed) {
  const RobotModel model = RobotModel::from_urdf_string(hand_urdf(0.3), ".");
  const int hand = model.link_index("hand");
  KinematicsState state(model);
  forward_kinematics(model, Eigen::VectorXd::Zero(model.num_joints()), state);
  const Eigen::Isometry3d T_camera_hand = T_camera_link(model, state, hand);
  const Eigen::Vector3d axis = T_camera_hand.linear().col(2);
  ImageInformation::RigidFit fit;
  fit.origin_m = T_camera_hand.translation();
  fit.pixels = 100;
  const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - axis * axis.transpose();
  fit.information.topLeftCorner<3, 3>() =
      across / (1e-4 * 1e-4) + axis * axis.transpose() / (1.5e-3 * 1.5e-3);
  fit.information.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() / (1e-3 * 1e-3);

  DepthModelParams params;
  params.width = kCamera160x120.width;
  params.height = kCamera160x120.height;
  DepthLikelihood likelihood(params);
  likelihood.set_observation(observed);
  DepthRenderer renderer(model, kCamera160x120);
  EndEffectorAxisSearch axis_search(model, {hand}, 0.01, 0.002);
  EXPECT_TRUE(axis_search.on());
  const std::vector<double> q(std::size_t(model.num_joints()), 0.0);
  const std::span<const Eigen::Vector3d> shifts =
      axis_search.search(renderer, likelihood, q, {fit});
  EXPECT_EQ(axis_search.searched(), 1);
  return {shifts[0], axis, axis_search.accepted()};
}

// The real wrist 6 mm longer: the hand is found 6 mm further along its
// axis, to within the grid's 2 mm and a pixel's 3.9 mm at 0.4 m (an
// image's score is a staircase at the pixels' size). The linear fit over
// the side face cannot see it.
TEST(EndEffectorAxisSearch, FindsAHandFurtherAlongItsOwnAxis) {
  const RobotModel truth = RobotModel::from_urdf_string(hand_urdf(0.306), ".");
  const Searched s = search(render(truth));
  EXPECT_EQ(s.accepted, 1);
  const double along_m = s.shift_m.dot(s.hand_axis);
  EXPECT_NEAR(along_m, 0.006, 0.0025);
  EXPECT_LT((s.shift_m - along_m * s.hand_axis).norm(), 1e-12);
}

// A hand that matches its model is not moved: no shift beats the fit's own
// pose by the test's margin.
TEST(EndEffectorAxisSearch, AHandThatMatchesItsModelStaysPut) {
  const RobotModel nominal = RobotModel::from_urdf_string(hand_urdf(0.3), ".");
  const Searched s = search(render(nominal));
  EXPECT_EQ(s.accepted, 0);
  EXPECT_EQ(s.shift_m, Eigen::Vector3d::Zero());
}

// A plate 5 cm in front of the hand's upper half: what it covers is
// explained as occluded at every shift, and the rest of the hand, where
// the model is, holds it there.
TEST(EndEffectorAxisSearch, APlateInFrontOfTheHandDoesNotDragIt) {
  const RobotModel nominal = RobotModel::from_urdf_string(hand_urdf(0.3), ".");
  DepthImage observed = render(nominal);
  int covered = 0;
  for (int v = 0; v < kCamera160x120.height; ++v)
    for (int u = 0; u < kCamera160x120.width; ++u) {
      float& z = observed.depth_m[std::size_t(v) * kCamera160x120.width + u];
      // The hand's upper half: above the camera's centre row (z 0.36 m).
      if (z > 0 && v < kCamera160x120.cy) {
        z -= 0.05f;
        ++covered;
      }
    }
  ASSERT_GT(covered, 200);
  const Searched s = search(observed);
  EXPECT_EQ(s.accepted, 0);
  EXPECT_EQ(s.shift_m, Eigen::Vector3d::Zero());
}

TEST(EndEffectorAxisSearch, OffWithoutARangeOrLinks) {
  const RobotModel model = RobotModel::from_urdf_string(hand_urdf(0.3), ".");
  EXPECT_FALSE(EndEffectorAxisSearch(model, {model.link_index("hand")}, 0.0, 0.002).on());
  EXPECT_FALSE(EndEffectorAxisSearch(model, {}, 0.01, 0.002).on());
}

}  // namespace
}  // namespace arttrack
