// Physics of a scene: MuJoCo stepping with position servos following
// commanded joint targets, direct state setting for tests, and ground truth
// at every step.
//
// Joint vectors are in SimModel::joint_names order (URDF joint names, mapped
// to MuJoCo's qpos/qvel addresses by name), radians (metres for prismatic
// joints). Poses: T_a_b maps b coordinates to a; "world" is the URDF root
// link's frame at the origin; "camera" is the optical frame of the camera
// link (z forward, x right, y down).
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Geometry>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "arttrack/sim/sim_model.h"

namespace arttrack::sim {

struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

// Everything true about the robot at one instant.
struct GroundTruth {
  double time_s = 0;
  Eigen::VectorXd q;   // joint angles (rad; m for prismatic)
  Eigen::VectorXd dq;  // joint velocities (rad/s; m/s)
  // Generalised forces at each joint's degree of freedom (N m; N):
  Eigen::VectorXd actuator_torque;    // what the servo applies (qfrc_actuator)
  Eigen::VectorXd bias_torque;        // gravity + Coriolis + centrifugal (qfrc_bias)
  Eigen::VectorXd constraint_torque;  // joint limits and contacts (qfrc_constraint)
  // Load the joint carries: what the servo must supply to hold the links
  // against gravity and contact, qfrc_bias - qfrc_constraint - qfrc_passive.
  Eigen::VectorXd load_torque;
  std::vector<Eigen::Isometry3d> T_world_link;  // SimModel::link_names order
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();
  // End effectors (SimModel::end_effector_names, e.g. left_ee, right_ee) in
  // the camera's optical frame.
  std::vector<Eigen::Isometry3d> T_camera_ee;
};

// Joint targets as a function of time: fills `q_target` (joint_names order).
using TargetFunction = std::function<void(double time_s, Eigen::VectorXd& q_target)>;

class Simulator {
 public:
  // Starts at the scene's initial joint configuration, at rest, servos
  // holding it, occluders at their scene poses.
  explicit Simulator(std::shared_ptr<const SimModel> model);

  const SimModel& model() const { return *model_; }
  const std::shared_ptr<const SimModel>& model_ptr() const { return model_; }
  mjData* data() { return data_.get(); }
  const mjData* data() const { return data_.get(); }
  double time_s() const { return data_->time; }

  // Back to the initial state at time 0.
  void reset();
  // Sets the joints (zero velocity) and the servo targets to q, recomputes
  // all poses (mj_forward). Time does not change.
  void set_joint_positions(const Eigen::VectorXd& q);
  // Servo targets for the next steps (clamped by MuJoCo to joint limits).
  void set_targets(const Eigen::VectorXd& q_target);
  // Moves an occluder (SimModel::occluder_names index) to a world pose.
  void set_occluder_pose(int occluder, const Eigen::Isometry3d& T_world_occluder);

  // One physics step of the scene's timestep, then all poses and forces are
  // recomputed for the new state (mj_step, mj_forward). Unstable physics (a
  // MuJoCo bad-state warning, its automatic reset of the clock, or a
  // non-finite state) throws InputError naming the simulated time and the
  // likely cause, instead of carrying on from a reset state.
  void step();
  // Steps until time_s() >= t_s (within half a step), asking `targets` for
  // the servo targets before every step (none: keep the current targets).
  void run_until(double t_s, const TargetFunction& targets = {});

  // Ground truth of the current state. Reuses `out`'s storage.
  void ground_truth(GroundTruth& out) const;
  GroundTruth ground_truth() const;

  // World pose of a MuJoCo body (current state).
  Eigen::Isometry3d T_world_body(int body) const;

 private:
  std::shared_ptr<const SimModel> model_;
  std::unique_ptr<mjData, MjDataDeleter> data_;
  Eigen::VectorXd target_;  // scratch for run_until
};

}  // namespace arttrack::sim
