// Forward kinematics: the pose of every link for a joint configuration.
//
// Poses are T_root_link (maps link coordinates to the URDF root link's
// frame), double precision, composed exactly as URDF specifies:
//   T_root_child = T_root_parent * T_parent_joint * M(q),
// with M(q) a rotation by q radians about the joint axis (revolute,
// continuous) or a translation by q metres along it (prismatic); a mimic
// joint's q is multiplier * q_leader + offset.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "arttrack/tracker/robot_model.h"

namespace arttrack {

// Per-thread workspace of forward kinematics (the mjData of this module).
struct KinematicsState {
  // Pose of each link in the root frame, indexed by link.
  std::vector<Eigen::Isometry3d> T_root_link;

  KinematicsState() = default;
  // Sized for `model`, so forward_kinematics never allocates.
  explicit KinematicsState(const RobotModel& model);
};

// Computes every link pose for joint positions q (size model.num_joints(),
// DOF order, radians or metres) in one pass over the links in topological
// order. Allocation-free once `state` is sized for the model.
void forward_kinematics(const RobotModel& model, const Eigen::VectorXd& q, KinematicsState& state);

// Pose of `link` in the corrected camera frame (model.camera_link()):
// T_camera_link = T_root_camera^-1 T_root_link, from a computed state.
Eigen::Isometry3d T_camera_link(const RobotModel& model, const KinematicsState& state, int link);

}  // namespace arttrack
