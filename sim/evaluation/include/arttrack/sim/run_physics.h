// The physics of one run of a scenario, stepped as `arttrack run` steps it:
// the simulator's servos following the run's commanded motion, the
// scenario's loads hung on its links, its occluders where their schedules
// put them. The runner advances it one joint period at a time and reads the
// sensors in between; `arttrack render --time` advances it to an instant.
// One loop for both, so a render shows the scene the run's camera saw.
#pragma once

#include <vector>

#include "arttrack/sim/motion.h"
#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scene.h"
#include "arttrack/sim/simulator.h"

namespace arttrack::sim {

// The scene a scenario's runs simulate: the scenario's scene with its
// simulated_urdf, and a physics time step cut so that a whole number of
// steps (at most the scene's own step) makes one joint period.
SceneDescription run_scene(const Scenario& scenario);

class RunPhysics {
 public:
  // `sim` simulates a model built from run_scene(scenario) (with the run's
  // model error); `motion` is the run's commanded motion for its joints
  // (run_trajectory). Resets the simulator to time 0, the occluders at
  // their first poses. Keeps references to `scenario` and `sim`.
  RunPhysics(const Scenario& scenario, Simulator& sim, JointTrajectory motion);

  double joint_period_s() const { return joint_period_s_; }

  // One joint period of physics: before every step, the servos' targets at
  // that step's time and the loads' forces.
  void advance_period();

  // Whole joint periods up to the one nearest `time_s` (no further back
  // than now), then the occluders at that time: the scene a camera frame
  // captured at that joint step shows.
  void advance_to(double time_s);

  // The occluders where their schedules put them at `time_s`.
  void place_occluders(double time_s);

 private:
  const Scenario& scenario_;
  Simulator& sim_;
  JointTrajectory motion_;
  double joint_period_s_;
  int substeps_;
  std::vector<int> load_body_;  // per scenario load: the body it hangs on
  Eigen::VectorXd target_;      // servo targets, per simulated joint
};

}  // namespace arttrack::sim
