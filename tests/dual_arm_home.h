// The home pose of the project's dual-arm robot (models/dual_arm.urdf), for
// the tests and the benchmarks (tools/bench_tracker.cc) that pose it. Its one
// source is the default scene, models/scene_default.yaml, which starts the
// simulated robot there (robot.initial_joints_deg); hypothesis_evaluator_test
// checks it against the pose documented at the top of the URDF.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <map>
#include <string>

#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/units.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::test_support {

// Joint name -> angle (rad) of the home pose, every joint the scene names.
inline std::map<std::string, double> dual_arm_home_rad() {
  const YamlDocument scene =
      load_yaml_file(std::string(ARTTRACK_SOURCE_DIR) + "/models/scene_default.yaml");
  std::map<std::string, double> home;
  for (const auto& joint : scene.root["robot"]["initial_joints_deg"])
    home[joint.first.as<std::string>()] = joint.second.as<double>() * kRadPerDeg;
  return home;
}

// The home pose as a configuration of `model`: the joints of the pose it
// has at their angles, the others (the virtual camera joints) at 0. Joints
// it lacks are skipped, so that another robot can stand in.
inline Eigen::VectorXd dual_arm_home_pose(const RobotModel& model) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  const std::vector<std::string>& names = model.joint_names();
  for (const auto& [name, rad] : dual_arm_home_rad()) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) q[it - names.begin()] = rad;
  }
  return q;
}

}  // namespace arttrack::test_support
