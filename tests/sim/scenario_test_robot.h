// A small dual-arm robot for the scenario tests, with the joint naming of the
// project's robot (left_arm_joint_*, right_arm_joint_*, head_pan_joint,
// head_tilt_joint, left_ee, right_ee, camera_optical_frame) and its joint
// groups and tracker settings in the scene, and a head camera that sees both arms: two-link arms
// reaching forward (+x) at shoulder height 1 m, the head 0.5 m behind the
// shoulders at 1.6 m, tilted down 40 degrees in the scene.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "../scratch_dir.h"

namespace arttrack::sim::test {

constexpr char kRobotUrdf[] = R"(<robot name="mini_dual_arm">
  <link name="base_link">
    <visual><origin xyz="0 0 0.5"/><geometry><box size="0.3 0.4 1.0"/></geometry></visual>
    <inertial><mass value="10"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="left_arm_upper">
    <visual><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.07 0.07"/></geometry></visual>
    <inertial><origin xyz="0.15 0 0"/><mass value="0.5"/>
      <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="left_arm_fore">
    <visual><origin xyz="0.125 0 0"/><geometry><box size="0.25 0.06 0.06"/></geometry></visual>
    <inertial><origin xyz="0.125 0 0"/><mass value="0.3"/>
      <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="left_ee"/>
  <link name="right_arm_upper">
    <visual><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.07 0.07"/></geometry></visual>
    <inertial><origin xyz="0.15 0 0"/><mass value="0.5"/>
      <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="right_arm_fore">
    <visual><origin xyz="0.125 0 0"/><geometry><box size="0.25 0.06 0.06"/></geometry></visual>
    <inertial><origin xyz="0.125 0 0"/><mass value="0.3"/>
      <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="right_ee"/>
  <link name="head_pan_link">
    <inertial><mass value="0.2"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="head_tilt_link">
    <inertial><mass value="0.2"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="camera_optical_frame"/>

  <joint name="left_arm_joint_1" type="revolute">
    <parent link="base_link"/><child link="left_arm_upper"/>
    <origin xyz="0 0.25 1.0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="200" velocity="2"/>
  </joint>
  <joint name="left_arm_joint_2" type="revolute">
    <parent link="left_arm_upper"/><child link="left_arm_fore"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="200" velocity="2"/>
  </joint>
  <joint name="left_ee_joint" type="fixed">
    <parent link="left_arm_fore"/><child link="left_ee"/><origin xyz="0.25 0 0"/>
  </joint>
  <joint name="right_arm_joint_1" type="revolute">
    <parent link="base_link"/><child link="right_arm_upper"/>
    <origin xyz="0 -0.25 1.0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="200" velocity="2"/>
  </joint>
  <joint name="right_arm_joint_2" type="revolute">
    <parent link="right_arm_upper"/><child link="right_arm_fore"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="200" velocity="2"/>
  </joint>
  <joint name="right_ee_joint" type="fixed">
    <parent link="right_arm_fore"/><child link="right_ee"/><origin xyz="0.25 0 0"/>
  </joint>
  <joint name="head_pan_joint" type="revolute">
    <parent link="base_link"/><child link="head_pan_link"/>
    <origin xyz="-0.5 0 1.5"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="50" velocity="2"/>
  </joint>
  <joint name="head_tilt_joint" type="revolute">
    <parent link="head_pan_link"/><child link="head_tilt_link"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1.2" effort="50" velocity="2"/>
  </joint>
  <joint name="camera_joint" type="fixed">
    <parent link="head_tilt_link"/><child link="camera_optical_frame"/>
    <origin xyz="0.05 0 0" rpy="-1.5707963267948966 0 -1.5707963267948966"/>
  </joint>
</robot>)";

// The scene around it: no floor (nothing but the robot and occluders in
// view), a 160x120 camera.
constexpr char kSceneYaml[] = R"(
robot:
  urdf: robot.urdf
  initial_joints_deg: {head_tilt_joint: 40}
  end_effectors: [left_ee, right_ee]
  groups:
    left_arm: [left_arm_joint_1, left_arm_joint_2]
    right_arm: [right_arm_joint_1, right_arm_joint_2]
    head: [head_pan_joint, head_tilt_joint]
    arms: [left_arm, right_arm]
  tracker_overrides:
    joints.per_joint.head_pan_joint.estimate_bias: false
    joints.per_joint.head_tilt_joint.estimate_bias: false
camera: {width: 160, height: 120, fovy_deg: 50}
actuators: {kp: 400, kv: 40}
floor: false
)";

// A scenario whose measurements take every path from the simulator to the
// trackers (dataset export and tracking, replay): latency, jitter and drops
// (arrival differs from stamp, some frames never come), depth noise and
// dropout, the depth's scale and the reported focal length off (the
// trackers get the reported intrinsics), biased noisy encoders, a camera
// offset; every 70 joint steps
// scored too (so from 0 s on); two end effectors; tracker overrides.
constexpr char kMeasuredScenario[] = R"(
scene: scene.yaml
duration_s: 1.5
seed: 5
methods: [encoders_only, camera_offset_only, full_fusion, vision_only]
camera: {width: 80, height: 60, latency_s: 0.04, jitter_s: 0.015, drop_probability: 0.1,
         noise_sigma0_m: 0.002, dropout_probability: 0.05, depth_scale_error: 0.003,
         focal_error: 0.02}
motion:
  sinusoids:
    - {joints: [left_arm_joint_1], amplitude_deg: 15, frequency_hz: 0.5}
    - {joints: [right_arm_joint_2], amplitude_deg: 20, frequency_hz: 0.4, phase_deg: 90}
encoders:
  - {joints: [arms], offset_deg: 5, noise_deg: 0.05}
miscalibration:
  camera_offset: {xyz_m: [0.01, -0.01, 0.02], rpy_deg: [1, -1, 0.5]}
scoring: {converged_after_s: 0.5, every_n_joint_steps: 70, end_effectors: [left_ee, right_ee]}
tracker_overrides: {particle_filter.particles: 10}
)";

// A short scenario for the tests that run it many times (sweeps, tuning):
// 1.5 s of the left shoulder swinging 10 degrees at 0.4 Hz, the arms'
// encoders 5 degrees off, left_ee scored from 0.5 s, a 40x30 likelihood.
// `methods` as the YAML lists them ("[full_fusion]"); `tracker_overrides`:
// more of them, each followed by ", ".
inline std::string short_scenario(int seed, const std::string& methods,
                                  const std::string& tracker_overrides = "") {
  return "\nscene: scene.yaml\nduration_s: 1.5\nseed: " + std::to_string(seed) +
         "\nmethods: " + methods + R"(
motion:
  sinusoids:
    - {joints: [left_arm_joint_1], amplitude_deg: 10, frequency_hz: 0.4}
encoders:
  - {joints: [arms], offset_deg: 5}
scoring: {converged_after_s: 0.5, end_effectors: [left_ee]}
tracker_overrides: {)" +
         tracker_overrides + "depth_model.width: 40, depth_model.height: 30}\n";
}

// A scratch folder (scratch_dir.h) with robot.urdf and scene.yaml, plus any
// other files written with write(); named after the test so that tests never
// share one.
class TestDir : public test_support::ScratchDir {
 public:
  explicit TestDir(const std::string& name) : ScratchDir(name) {
    write("robot.urdf", kRobotUrdf);
    write("scene.yaml", kSceneYaml);
  }
};

}  // namespace arttrack::sim::test
