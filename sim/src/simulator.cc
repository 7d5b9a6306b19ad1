#include "arttrack/sim/simulator.h"

#include <cassert>

namespace arttrack::sim {

Simulator::Simulator(std::shared_ptr<const SimModel> model)
    : model_(std::move(model)), data_(mj_makeData(model_->mj.get())) {
  reset();
}

void Simulator::reset() {
  const mjModel* m = model_->mj.get();
  mj_resetData(m, data_.get());  // qpos0, mocap bodies at their model poses
  set_joint_positions(model_->initial_joints);
}

void Simulator::set_joint_positions(const Eigen::VectorXd& q) {
  assert(q.size() == Eigen::Index(model_->joint_names.size()));
  mjData* d = data_.get();
  for (size_t i = 0; i < model_->joint_names.size(); ++i) {
    d->qpos[model_->joint_qpos_adr[i]] = q[i];
    d->qvel[model_->joint_dof_adr[i]] = 0;
    d->ctrl[model_->joint_actuator[i]] = q[i];
  }
  mj_forward(model_->mj.get(), d);
}

void Simulator::set_targets(const Eigen::VectorXd& q_target) {
  assert(q_target.size() == Eigen::Index(model_->joint_names.size()));
  for (size_t i = 0; i < model_->joint_names.size(); ++i)
    data_->ctrl[model_->joint_actuator[i]] = q_target[i];
}

void Simulator::set_occluder_pose(int occluder, const Eigen::Isometry3d& T_world_occluder) {
  const int k = model_->occluder_mocap[occluder];
  const Eigen::Quaterniond q(T_world_occluder.linear());
  const Eigen::Vector3d p = T_world_occluder.translation();
  for (int i = 0; i < 3; ++i) data_->mocap_pos[3 * k + i] = p[i];
  data_->mocap_quat[4 * k + 0] = q.w();
  data_->mocap_quat[4 * k + 1] = q.x();
  data_->mocap_quat[4 * k + 2] = q.y();
  data_->mocap_quat[4 * k + 3] = q.z();
  // Mocap poses enter the body poses in kinematics; keep everything current.
  mj_forward(model_->mj.get(), data_.get());
}

void Simulator::step() {
  const mjModel* m = model_->mj.get();
  mj_step(m, data_.get());
  // mj_step leaves positions-derived quantities (poses, forces) at the state
  // before integration; recompute them for the state after it.
  mj_forward(m, data_.get());
}

void Simulator::run_until(double t_s, const TargetFunction& targets) {
  const double half_step = 0.5 * model_->mj->opt.timestep;
  target_.resize(Eigen::Index(model_->joint_names.size()));
  while (data_->time < t_s - half_step) {
    if (targets) {
      targets(data_->time, target_);
      set_targets(target_);
    }
    step();
  }
}

Eigen::Isometry3d Simulator::T_world_body(int body) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const mjtNum* p = data_->xpos + 3 * body;
  const mjtNum* R = data_->xmat + 9 * body;  // row-major
  T.translation() << p[0], p[1], p[2];
  T.linear() << R[0], R[1], R[2], R[3], R[4], R[5], R[6], R[7], R[8];
  return T;
}

void Simulator::ground_truth(GroundTruth& out) const {
  const mjData* d = data_.get();
  const SimModel& sm = *model_;
  const auto n = Eigen::Index(sm.joint_names.size());
  out.time_s = d->time;
  out.q.resize(n);
  out.dq.resize(n);
  out.actuator_torque.resize(n);
  out.bias_torque.resize(n);
  out.constraint_torque.resize(n);
  out.load_torque.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int dof = sm.joint_dof_adr[i];
    out.q[i] = d->qpos[sm.joint_qpos_adr[i]];
    out.dq[i] = d->qvel[dof];
    out.actuator_torque[i] = d->qfrc_actuator[dof];
    out.bias_torque[i] = d->qfrc_bias[dof];
    out.constraint_torque[i] = d->qfrc_constraint[dof];
    out.load_torque[i] = d->qfrc_bias[dof] - d->qfrc_constraint[dof] - d->qfrc_passive[dof];
  }
  out.T_world_link.resize(sm.link_body.size());
  for (size_t i = 0; i < sm.link_body.size(); ++i)
    out.T_world_link[i] = T_world_body(sm.link_body[i]);
  out.T_world_camera = T_world_body(sm.camera_body);
  const Eigen::Isometry3d T_camera_world = out.T_world_camera.inverse();
  out.T_camera_ee.resize(sm.end_effector_body.size());
  for (size_t i = 0; i < sm.end_effector_body.size(); ++i)
    out.T_camera_ee[i] = T_camera_world * T_world_body(sm.end_effector_body[i]);
}

GroundTruth Simulator::ground_truth() const {
  GroundTruth g;
  ground_truth(g);
  return g;
}

}  // namespace arttrack::sim
