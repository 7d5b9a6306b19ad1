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

void camera_link_jacobian(const RobotModel& model, const KinematicsState& state, int link,
                          Eigen::Matrix<double, 6, Eigen::Dynamic>& J) {
  ARTTRACK_CHECK_ARGUMENT(link >= 0 && link < model.num_links());
  ARTTRACK_CHECK_ARGUMENT(int(state.T_root_link.size()) == model.num_links());
  if (J.cols() != model.num_joints()) J.resize(6, model.num_joints());
  J.setZero();
  const std::vector<Eigen::Isometry3d>& T = state.T_root_link;
  const Eigen::Vector3d p = T[link].translation();  // the link's origin, root frame
  // Each moving joint on the chain from `from` to the root adds sign times
  // its motion of the point p, in root axes.
  auto add_chain = [&](int from, double sign) {
    for (int l = from; l > 0; l = model.link(l).parent) {
      const Link& joint = model.link(l);
      const int column = joint.dof >= 0 ? joint.dof : joint.mimic_dof;
      if (joint.joint_type == JointType::kFixed || column < 0) continue;
      const double rate = sign * (joint.dof >= 0 ? 1.0 : joint.mimic_multiplier);
      const Eigen::Vector3d a =
          T[joint.parent].linear() * (joint.T_parent_joint.linear() * joint.axis);
      if (joint.joint_type == JointType::kPrismatic) {
        J.col(column).head<3>() += rate * a;
      } else {
        // A revolute joint's origin is its child link's: the rotation does
        // not move it.
        J.col(column).head<3>() += rate * a.cross(p - T[l].translation());
        J.col(column).tail<3>() += rate * a;
      }
    }
  };
  add_chain(link, 1.0);
  add_chain(model.camera_link(), -1.0);
  // Root axes to camera axes (column by column: fixed-size, no temporary).
  const Eigen::Matrix3d R_camera_root = T[model.camera_link()].linear().transpose();
  for (Eigen::Index c = 0; c < J.cols(); ++c) {
    const Eigen::Vector3d v = J.col(c).head<3>(), w = J.col(c).tail<3>();
    J.col(c).head<3>() = R_camera_root * v;
    J.col(c).tail<3>() = R_camera_root * w;
  }
}

}  // namespace arttrack
