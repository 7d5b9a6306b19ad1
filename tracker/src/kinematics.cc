#include "arttrack/tracker/kinematics.h"

#include "arttrack/tracker/error.h"

namespace arttrack {

KinematicsState::KinematicsState(const RobotModel& model)
    : T_root_link(model.num_links(), Eigen::Isometry3d::Identity()) {}

void forward_kinematics(const RobotModel& model, const Eigen::VectorXd& q, KinematicsState& state) {
  ARTTRACK_CHECK_ARGUMENT(q.size() == model.num_joints());
  const int n = model.num_links();
  if (int(state.T_root_link.size()) != n)
    state.T_root_link.assign(n, Eigen::Isometry3d::Identity());
  std::vector<Eigen::Isometry3d>& T = state.T_root_link;
  T[0].setIdentity();
  for (int l = 1; l < n; ++l) {
    const Link& link = model.link(l);
    const Eigen::Isometry3d& T_root_parent = T[link.parent];
    const Eigen::Matrix3d& R_parent_joint = link.T_parent_joint.linear();
    Eigen::Isometry3d& T_root_child = T[l];
    // Joint frame position first: it does not depend on the joint motion
    // except for prismatic joints, whose offset is added below.
    Eigen::Vector3d p_parent = link.T_parent_joint.translation();
    const double q_joint = link.dof >= 0 ? q[link.dof]
                           : link.mimic_dof >= 0
                               ? link.mimic_multiplier * q[link.mimic_dof] + link.mimic_offset
                               : 0.0;
    switch (link.joint_type) {
      case JointType::kFixed:
        T_root_child.linear() = T_root_parent.linear() * R_parent_joint;
        break;
      case JointType::kRevolute:
      case JointType::kContinuous: {
        const Eigen::Matrix3d R_joint_child =
            Eigen::AngleAxisd(q_joint, link.axis).toRotationMatrix();
        T_root_child.linear() = T_root_parent.linear() * (R_parent_joint * R_joint_child);
        break;
      }
      case JointType::kPrismatic:
        T_root_child.linear() = T_root_parent.linear() * R_parent_joint;
        p_parent += R_parent_joint * (link.axis * q_joint);
        break;
    }
    T_root_child.translation() = T_root_parent.linear() * p_parent + T_root_parent.translation();
  }
}

Eigen::Isometry3d T_camera_link(const RobotModel& model, const KinematicsState& state, int link) {
  return state.T_root_link[model.camera_link()].inverse(Eigen::Isometry) * state.T_root_link[link];
}

}  // namespace arttrack
