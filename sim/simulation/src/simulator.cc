#include "arttrack/sim/simulator.h"

#include <cmath>
#include <sstream>

#include "arttrack/tracker/error.h"

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
  ARTTRACK_CHECK_ARGUMENT(q.size() == Eigen::Index(model_->joint_names.size()));
  mjData* d = data_.get();
  for (size_t i = 0; i < model_->joint_names.size(); ++i) {
    d->qpos[model_->joint_qpos_adr[i]] = q[i];
    d->qvel[model_->joint_dof_adr[i]] = 0;
    d->ctrl[model_->joint_actuator[i]] = q[i];
  }
  mj_forward(model_->mj.get(), d);
}

void Simulator::set_targets(const Eigen::VectorXd& q_target) {
  ARTTRACK_CHECK_ARGUMENT(q_target.size() == Eigen::Index(model_->joint_names.size()));
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

namespace {

// MuJoCo's warnings that mean the state has blown up (a value not finite or
// beyond 1e10): it then resets the state (and the clock) and carries on.
constexpr mjtWarning kInstabilityWarnings[] = {mjWARN_BADQPOS, mjWARN_BADQVEL, mjWARN_BADQACC};

const char* warning_name(int w) {
  switch (w) {
    case mjWARN_BADQPOS:
      return "bad number in joint positions";
    case mjWARN_BADQVEL:
      return "bad number in joint velocities";
    case mjWARN_BADQACC:
      return "bad number in joint accelerations";
    default:
      return "warning";
  }
}

bool finite(const mjtNum* x, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) return false;
  return true;
}

}  // namespace

void Simulator::step() {
  const mjModel* m = model_->mj.get();
  mjData* d = data_.get();
  const double t_before = d->time;
  int warnings_before[mjNWARNING];
  for (int w = 0; w < mjNWARNING; ++w) warnings_before[w] = d->warning[w].number;
  mj_step(m, d);
  // mj_step leaves positions-derived quantities (poses, forces) at the state
  // before integration; recompute them for the state after it.
  mj_forward(m, d);

  const char* what = nullptr;
  for (mjtWarning w : kInstabilityWarnings) {
    if (d->warning[w].number > warnings_before[w]) {
      what = warning_name(w);
      break;
    }
  }
  if (!what && !(d->time > t_before)) what = "the clock was reset";
  if (!what && !(finite(d->qpos, m->nq) && finite(d->qvel, m->nv) && finite(d->qacc, m->nv)))
    what = "non-finite state";
  if (what) {
    std::ostringstream msg;
    msg << model_->scene.source << ": the physics went unstable at simulated time " << t_before
        << " s (MuJoCo: " << what << "); likely cause: a time step too large for the servos "
        << "(timestep_s = " << m->opt.timestep << "), too little damping, or extreme gravity ("
        << std::sqrt(m->opt.gravity[0] * m->opt.gravity[0] + m->opt.gravity[1] * m->opt.gravity[1] +
                     m->opt.gravity[2] * m->opt.gravity[2])
        << " m/s^2) or gains";
    throw InputError(msg.str());
  }
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
