// The simulator: servos under gravity settle where the closed-form static
// balance says, joints are mapped by name (not by order), ground truth poses
// match hand-computed kinematics, occluders move.
#include "arttrack/sim/simulator.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../scratch_dir.h"
#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;

using test_support::write_scratch_file;

// A planar two-link arm swinging about horizontal y axes. The joints are
// listed tip first, so URDF order differs from MuJoCo's tree order. Each link
// is a 2 kg point-like mass 0.25 m out along its x axis.
constexpr char kPlanarArmUrdf[] = R"(<robot name="arm">
  <link name="base_link"/>
  <joint name="b_elbow" type="revolute">
    <parent link="upper"/><child link="fore"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 -1 0"/>
    <limit lower="-2.5" upper="2.5" effort="100" velocity="2"/>
  </joint>
  <joint name="a_shoulder" type="revolute">
    <parent link="base_link"/><child link="upper"/>
    <origin xyz="0 0 1"/><axis xyz="0 -1 0"/>
    <limit lower="-2.5" upper="2.5" effort="100" velocity="2"/>
  </joint>
  <link name="upper">
    <inertial><origin xyz="0.25 0 0"/><mass value="2"/>
      <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0.25 0 0" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.03" length="0.5"/></geometry></visual>
  </link>
  <link name="fore">
    <collision><origin xyz="0.25 0 0" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.03" length="0.5"/></geometry></collision>
    <inertial><origin xyz="0.25 0 0"/><mass value="2"/>
      <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0.25 0 0" rpy="0 1.5707963267948966 0"/>
      <geometry><cylinder radius="0.03" length="0.5"/></geometry></visual>
  </link>
  <joint name="tool_joint" type="fixed">
    <parent link="fore"/><child link="tool"/><origin xyz="0.5 0 0"/>
  </joint>
  <link name="tool"/>
  <joint name="camera_joint" type="fixed">
    <parent link="base_link"/><child link="camera_optical_frame"/>
    <origin xyz="-1 0 1" rpy="-1.5707963267948966 0 -1.5707963267948966"/>
  </joint>
  <link name="camera_optical_frame"/>
</robot>)";

SceneDescription arm_scene(double kp, double kv) {
  SceneDescription s;
  s.urdf_path = write_scratch_file("arm.urdf", kPlanarArmUrdf);
  s.end_effector_links = {"tool"};
  s.default_gains = {kp, kv};
  s.armature_kg_m2 = 0.01;
  s.floor = false;
  s.width = 64;
  s.height = 48;
  return s;
}

// Positive joint angles lift the links (axis -y): a link at absolute angle
// phi from horizontal has its tip at (cos phi, sin phi) * length in x-z.
Eigen::Vector3d tip(double shoulder, double elbow) {
  return {0.5 * std::cos(shoulder) + 0.5 * std::cos(shoulder + elbow), 0,
          1 + 0.5 * std::sin(shoulder) + 0.5 * std::sin(shoulder + elbow)};
}

TEST(Simulator, JointsMappedByNameNotOrder) {
  const auto model = build_sim_model(arm_scene(100, 10));
  ASSERT_EQ(model->joint_names, (std::vector<std::string>{"b_elbow", "a_shoulder"}));
  Simulator sim(model);
  const double elbow = 0.7, shoulder = -0.3;
  sim.set_joint_positions(Eigen::Vector2d(elbow, shoulder));
  const GroundTruth g = sim.ground_truth();
  EXPECT_EQ(g.q[0], elbow);
  EXPECT_EQ(g.q[1], shoulder);
  const int tool = model->link_index("tool");
  EXPECT_LT((g.T_world_link[tool].translation() - tip(shoulder, elbow)).norm(), 1e-12);
  // The tool's x axis points along the forearm.
  const Eigen::Vector3d x_fore(std::cos(shoulder + elbow), 0, std::sin(shoulder + elbow));
  EXPECT_LT((g.T_world_link[tool].linear().col(0) - x_fore).norm(), 1e-12);
  // In the camera's optical frame (1 m behind the base, looking along +x):
  // optical x = -world y, y = -world z, z = world x.
  const Eigen::Vector3d p = tip(shoulder, elbow);
  const Eigen::Vector3d expected(0, 1 - p.z(), p.x() + 1);
  ASSERT_EQ(g.T_camera_ee.size(), 1u);
  EXPECT_LT((g.T_camera_ee[0].translation() - expected).norm(), 1e-12);
}

TEST(Simulator, ServoSettlesAtStaticBalanceUnderGravity) {
  const double kp = 400, kv = 40, g = 9.81, m = 2;
  const auto model = build_sim_model(arm_scene(kp, kv));
  Simulator sim(model);
  const double shoulder_target = 0.4, elbow_target = -0.6;
  sim.run_until(3.0, [&](double, Eigen::VectorXd& q) { q << elbow_target, shoulder_target; });
  const GroundTruth truth = sim.ground_truth();
  EXPECT_NEAR(truth.time_s, 3.0, 1e-9);
  // At rest, each servo's torque kp (target - q) balances gravity on the links
  // beyond it: elbow carries the forearm, the shoulder both links.
  const double q_e = truth.q[0], q_s = truth.q[1];
  const double tau_elbow = m * g * 0.25 * std::cos(q_s + q_e);
  const double tau_shoulder =
      m * g * 0.25 * std::cos(q_s) + m * g * (0.5 * std::cos(q_s)) + tau_elbow;
  EXPECT_NEAR(kp * (elbow_target - q_e), tau_elbow, 1e-3);
  EXPECT_NEAR(kp * (shoulder_target - q_s), tau_shoulder, 1e-3);
  EXPECT_LT(truth.dq.norm(), 1e-4);
  // Close to the target: the gravity sag tau / kp is about 0.046 rad at the
  // shoulder and 0.012 rad at the elbow.
  EXPECT_NEAR(q_s, shoulder_target, 0.05);
  EXPECT_NEAR(q_e, elbow_target, 0.015);
  // Ground-truth torques: the servo supplies exactly the gravity load.
  EXPECT_NEAR(truth.actuator_torque[1], tau_shoulder, 1e-3);
  EXPECT_NEAR(truth.bias_torque[1], tau_shoulder, 1e-3);
  EXPECT_NEAR(truth.load_torque[0], tau_elbow, 1e-3);
}

TEST(Simulator, TracksMovingTarget) {
  const auto model = build_sim_model(arm_scene(2000, 100));
  Simulator sim(model);
  sim.run_until(2.0, [](double t, Eigen::VectorXd& q) { q << 0.3 * std::sin(t), 0.2; });
  const GroundTruth truth = sim.ground_truth();
  EXPECT_NEAR(truth.q[0], 0.3 * std::sin(2.0), 0.03);
  sim.reset();
  EXPECT_EQ(sim.time_s(), 0);
  EXPECT_EQ(sim.ground_truth().q.norm(), 0);
}

TEST(Simulator, ArmStopsOnTableAndObjectsRestOnIt) {
  SceneDescription s = arm_scene(400, 40);
  SceneShape top;  // upper face at z = 0.7, under the forearm's sweep
  top.name = "table_top";
  top.size_m << 0.6, 0.6, 0.04;
  top.T_world_shape.translation() << 0.8, 0, 0.68;
  s.shapes.push_back(top);
  SceneShape crate;  // dropped from 5 cm above the table
  crate.name = "crate";
  crate.free = true;
  crate.size_m << 0.1, 0.1, 0.1;
  crate.T_world_shape.translation() << 0.9, 0.2, 0.8;
  s.shapes.push_back(crate);
  const auto model = build_sim_model(s);
  Simulator sim(model);
  // Shoulder level, elbow commanded far down, through the table.
  sim.run_until(2.0, [](double, Eigen::VectorXd& q) { q << -1.5, 0.0; });
  const GroundTruth truth = sim.ground_truth();
  const double tip_z = truth.T_world_link[model->link_index("tool")].translation().z();
  // At the targets the tip would be at z = 0.5, inside the table; it rests on
  // the table instead (the forearm's radius is 3 cm).
  EXPECT_GT(tip_z, 0.7 - 0.01);
  EXPECT_LT(tip_z, 0.7 + 0.06);
  EXPECT_GT(std::abs(truth.constraint_torque[0]), 1.0);
  const int body = mj_name2id(model->mj.get(), mjOBJ_BODY, "crate");
  EXPECT_NEAR(sim.T_world_body(body).translation().z(), 0.75, 0.005);
}

TEST(Simulator, OccluderMoves) {
  SceneDescription s = arm_scene(100, 10);
  OccluderSpec o;
  o.name = "board";
  o.size_m << 0.02, 0.5, 0.5;
  o.T_world_occluder.translation() << 5, 0, 0;
  s.occluders.push_back(o);
  const auto model = build_sim_model(s);
  Simulator sim(model);
  const int body = mj_name2id(model->mj.get(), mjOBJ_BODY, "occluder_board");
  EXPECT_NEAR(sim.T_world_body(body).translation().x(), 5, 1e-12);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << 0.3, 0.1, 1.2;
  T.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  sim.set_occluder_pose(model->occluder_index("board"), T);
  EXPECT_TRUE(sim.T_world_body(body).isApprox(T, 1e-12));
}

// Stiff servos without damping at a huge time step blow up. MuJoCo then
// resets the state and the clock and carries on (a loop waiting for the clock
// never ends); the simulator stops with an error naming the time instead.
TEST(Simulator, UnstablePhysicsIsAnErrorNamingTheTime) {
  SceneDescription s = arm_scene(1e6, 0);
  s.timestep_s = 0.1;
  s.gravity_m_s2 << 0, 0, -1e6;
  s.source = "unstable.yaml";
  const auto model = build_sim_model(s);
  Simulator sim(model);
  std::string message;
  for (int i = 0; i < 1000 && message.empty(); ++i) {
    try {
      sim.step();
    } catch (const InputError& e) {
      message = e.what();
    }
  }
  EXPECT_NE(message.find("unstable.yaml"), std::string::npos) << message;
  EXPECT_NE(message.find("unstable at simulated time"), std::string::npos) << message;
  EXPECT_NE(message.find("timestep_s = 0.1"), std::string::npos) << message;
}

}  // namespace
}  // namespace arttrack::sim
