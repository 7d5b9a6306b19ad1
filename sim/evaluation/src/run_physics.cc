#include "arttrack/sim/run_physics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "arttrack/sim/sim_model.h"

namespace arttrack::sim {

SceneDescription run_scene(const Scenario& scenario) {
  SceneDescription scene = scenario.scene;
  const double period_s = 1.0 / scenario.joint_rate_hz;
  const int substeps = std::max(1, int(std::ceil(period_s / scene.timestep_s - 1e-9)));
  scene.timestep_s = period_s / substeps;
  scene.urdf_path = scenario.simulated_urdf();
  return scene;
}

RunPhysics::RunPhysics(const Scenario& scenario, Simulator& sim, JointTrajectory motion)
    : scenario_(scenario),
      sim_(sim),
      motion_(std::move(motion)),
      joint_period_s_(1.0 / scenario.joint_rate_hz),
      substeps_(std::max(1, int(std::lround(joint_period_s_ / sim.model().mj->opt.timestep)))),
      target_(Eigen::Index(sim.model().joint_names.size())) {
  const SimModel& m = sim_.model();
  if (std::abs(substeps_ * m.mj->opt.timestep - joint_period_s_) > 1e-9 * joint_period_s_)
    throw std::logic_error(
        "RunPhysics: the simulator's time step does not divide the joint "
        "period (build its model from run_scene)");
  for (const LinkLoad& l : scenario_.loads) load_body_.push_back(m.link_body[m.link_index(l.link)]);
  sim_.reset();
  place_occluders(0);
}

void RunPhysics::advance_period() {
  mjData* d = sim_.data();
  const Eigen::Vector3d g = sim_.model().scene.gravity_m_s2;
  for (int k = 0; k < substeps_; ++k) {
    const double now = sim_.time_s();
    motion_.position(now, std::span<double>(target_.data(), std::size_t(target_.size())));
    sim_.set_targets(target_);
    // Loads add up: several may hang on one link (a held load and one not
    // picked up yet, at weight 0).
    for (int b : load_body_) std::fill_n(d->xfrc_applied + 6 * b, 6, 0.0);
    for (std::size_t i = 0; i < scenario_.loads.size(); ++i) {
      // MuJoCo applies xfrc_applied at the body's centre of mass (xipos),
      // which for a massless link frame is not the frame; the torque term
      // moves the force to the link frame's origin (xpos).
      const LinkLoad& l = scenario_.loads[i];
      const int b = load_body_[i];
      const Eigen::Vector3d f = l.weight(now) * l.mass_kg * g;
      const Eigen::Vector3d lever = Eigen::Map<const Eigen::Vector3d>(d->xpos + 3 * b) -
                                    Eigen::Map<const Eigen::Vector3d>(d->xipos + 3 * b);
      const Eigen::Vector3d torque = lever.cross(f);
      for (int a = 0; a < 3; ++a) {
        d->xfrc_applied[6 * b + a] += f[a];
        d->xfrc_applied[6 * b + 3 + a] += torque[a];
      }
    }
    sim_.step();
  }
}

void RunPhysics::advance_to(double time_s) {
  // The runner's joint step n is at n periods; count them rather than
  // compare times, which drift by rounding over thousands of steps.
  const long now = std::lround(sim_.time_s() / joint_period_s_);
  const long target = std::max(now, std::lround(time_s / joint_period_s_));
  for (long n = now; n < target; ++n) advance_period();
  place_occluders(double(target) * joint_period_s_);
}

void RunPhysics::place_occluders(double time_s) {
  for (const OccluderSchedule& o : scenario_.occluder_schedules)
    sim_.set_occluder_pose(o.occluder, o.pose_at(time_s));
}

}  // namespace arttrack::sim
