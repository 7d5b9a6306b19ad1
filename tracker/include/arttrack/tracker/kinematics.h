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

// The Jacobian of T_camera_link(link) in q at a computed state, into J (6 x
// model.num_joints(), resized if needed): column j is the velocity of the
// link's origin (m per unit of q_j) over the angular velocity (rad per
// unit), both in the camera frame; the rotation is applied on the left
// (R_camera_link(q + dq) ~ exp([J_rot dq]x) R_camera_link(q)). A joint
// between the root and the link moves it about (along) the joint axis
// through the joint origin: [a x (p - o); a]; one between the root and the
// camera moves the camera, so the link by minus that; a joint above both
// moves neither relative to the other. A mimic joint adds its multiplier
// times its own column to its leader's. Closed form, one pass up each
// chain: the same as central differences of T_camera_link (tested against
// them), without the 2 num_joints() kinematics passes. Allocation-free
// once J has its size.
void camera_link_jacobian(const RobotModel& model, const KinematicsState& state, int link,
                          Eigen::Matrix<double, 6, Eigen::Dynamic>& J);

}  // namespace arttrack
