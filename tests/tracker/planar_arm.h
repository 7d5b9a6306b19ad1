// The tracker tests' robot: a two-joint planar arm of boxes in front of a
// camera, the small configuration they track it with, and the depth a
// perfect camera sees of it. Shared by the tracker's tests and its
// components' (tests/tracker/*_test.cc).
#pragma once

#include <algorithm>
#include <memory>

#include <Eigen/Core>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"
#include "arttrack/tracker/units.h"

namespace arttrack::test_support {

// A two-joint planar arm of boxes in front of a camera that looks at it
// along the base's x axis, with an end-effector frame at the tip.
inline constexpr char kArm[] = R"(<robot name="arm">
  <link name="base_link"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <link name="upper"><visual><origin xyz="0 0 0.15"/><geometry><box size="0.05 0.06 0.3"/></geometry></visual></link>
  <link name="lower"><visual><origin xyz="0 0 0.125"/><geometry><box size="0.04 0.08 0.25"/></geometry></visual></link>
  <link name="tool"/>
  <link name="camera_optical_frame"/>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="upper"/>
    <origin xyz="0 0 0.05"/><axis xyz="1 0 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="0 0 0.3"/><axis xyz="1 0 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="lower"/><child link="tool"/><origin xyz="0 0 0.25"/></joint>
  <joint name="camera_joint" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="1.0 0 0.3" rpy="-1.5707963267948966 0 1.5707963267948966"/></joint>
</robot>)";

inline std::shared_ptr<const RobotModel> arm_model() {
  return std::make_shared<const RobotModel>(RobotModel::from_urdf_string(kArm, "."));
}

inline TrackerConfig small_config(TrackingMethod method) {
  TrackerConfig c;
  c.method = method;
  c.end_effectors = {"tool"};
  c.particle_filter.num_particles = 40;
  c.min_evaluations = 0;  // exactly 40 per block
  c.threads = 1;
  c.depth_model.width = 64;
  c.depth_model.height = 48;
  // A planar arm cannot tell a shoulder rotation from a camera roll about a
  // nearby axis: the camera is known here, so that joint angles are observable.
  c.camera_translation = {1e-9, 1e-9};
  c.camera_rotation = {1e-9, 1e-9};
  return c;
}

inline const CameraIntrinsics kCamera =
    CameraIntrinsics::from_vertical_fov(64, 48, 60 * kRadPerDeg);

// The depth a perfect camera (kCamera unless given) sees of the arm at
// angles q.
inline DepthImage render_truth(const RobotModel& model, double q0, double q1,
                               const CameraIntrinsics& camera = kCamera) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  q[model.joint_index("shoulder")] = q0;
  q[model.joint_index("elbow")] = q1;
  KinematicsState state(model);
  forward_kinematics(model, q, state);
  DepthRenderer renderer(model, camera);
  DepthImage image;
  renderer.render(state, image);
  return image;
}

// The pixels `image` holds a depth in.
inline int drawn_pixels(const DepthImage& image) {
  return int(
      std::count_if(image.depth_m.begin(), image.depth_m.end(), [](float z) { return z > 0; }));
}

}  // namespace arttrack::test_support
