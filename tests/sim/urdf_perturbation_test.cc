// URDF perturbation: checked against forward kinematics of the nominal
// robot composed by hand with the requested change (camera offset, neck
// origin and axis error, link length), against mesh bounds (shape scale),
// and against MuJoCo (the simulator's true camera is the nominal one moved by
// exactly the offset). The user's file is never changed.
#include "arttrack/sim/urdf_perturbation.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "../expect_error.h"
#include "arttrack/sim/simulator.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/units.h"
#include "scenario_test_robot.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;
using test_support::expect_error_naming;

Eigen::Matrix3d rpy(double r, double p, double y) {
  return (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Isometry3d pose(const Eigen::Vector3d& xyz, const Eigen::Matrix3d& R) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = xyz;
  T.linear() = R;
  return T;
}

RobotModel model_of(const std::string& urdf, const std::string& base_dir = ".") {
  RobotModelOptions o;
  o.add_virtual_camera_joints = false;
  return RobotModel::from_urdf_string(urdf, base_dir, o);
}

// Pose of `link` in the root frame at joint angles given by name.
Eigen::Isometry3d fk(const RobotModel& model, const std::map<std::string, double>& q_by_name,
                     const std::string& link) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  for (const auto& [name, value] : q_by_name) q[model.joint_index(name)] = value;
  KinematicsState state(model);
  forward_kinematics(model, q, state);
  return state.T_root_link[model.link_index(link)];
}

std::string perturb(const UrdfPerturbation& p) {
  return perturb_urdf_text(test::kRobotUrdf, "robot.urdf", ".", {}, p);
}

// Random head and arm configurations within the limits.
std::vector<std::map<std::string, double>> configurations(int n) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  std::vector<std::map<std::string, double>> out;
  for (int i = 0; i < n; ++i)
    out.push_back({{"head_pan_joint", u(rng)},
                   {"head_tilt_joint", u(rng)},
                   {"left_arm_joint_1", u(rng)},
                   {"left_arm_joint_2", u(rng)}});
  return out;
}

TEST(UrdfPerturbation, CameraOffsetMovesTheCameraByExactlyTheOffset) {
  UrdfPerturbation p;
  p.T_nominal_true_camera =
      pose({0.01, -0.02, 0.03}, rpy(1 * kRadPerDeg, -2 * kRadPerDeg, 3 * kRadPerDeg));
  const RobotModel nominal = model_of(test::kRobotUrdf), perturbed = model_of(perturb(p));
  for (const auto& q : configurations(5)) {
    const Eigen::Isometry3d expected =
        fk(nominal, q, "camera_optical_frame") * p.T_nominal_true_camera;
    EXPECT_LT((fk(perturbed, q, "camera_optical_frame").matrix() - expected.matrix()).norm(),
              1e-12);
    // Nothing else moves.
    EXPECT_LT((fk(perturbed, q, "left_ee").matrix() - fk(nominal, q, "left_ee").matrix()).norm(),
              1e-12);
  }
}

TEST(UrdfPerturbation, HeadErrorDependsOnTheHeadPose) {
  UrdfPerturbation p;
  JointOriginChange c;
  c.joint = "head_tilt_joint";
  c.T_old_new = pose({0, 0.01, 0.005}, rpy(0, 0, 2 * kRadPerDeg));
  c.R_axis = rpy(3 * kRadPerDeg, 0, 0);
  p.joint_changes.push_back(c);
  const RobotModel nominal = model_of(test::kRobotUrdf), perturbed = model_of(perturb(p));

  std::vector<Eigen::Isometry3d> camera_errors;
  for (const auto& q : configurations(5)) {
    // By hand: pan joint, then the changed tilt origin, the tilted axis, the camera mount.
    const double pan = q.at("head_pan_joint"), tilt = q.at("head_tilt_joint");
    const Eigen::Vector3d axis = c.R_axis * Eigen::Vector3d::UnitY();
    const Eigen::Isometry3d expected =
        pose({-0.5, 0, 1.5}, Eigen::Matrix3d::Identity()) *
        pose(Eigen::Vector3d::Zero(), Eigen::AngleAxisd(pan, Eigen::Vector3d::UnitZ()).matrix()) *
        pose({0, 0, 0.1}, Eigen::Matrix3d::Identity()) * c.T_old_new *
        pose(Eigen::Vector3d::Zero(), Eigen::AngleAxisd(tilt, axis).matrix()) *
        pose({0.05, 0, 0}, rpy(-M_PI / 2, 0, -M_PI / 2));
    const Eigen::Isometry3d actual = fk(perturbed, q, "camera_optical_frame");
    EXPECT_LT((actual.matrix() - expected.matrix()).norm(), 1e-12);
    camera_errors.push_back(fk(nominal, q, "camera_optical_frame").inverse() * actual);
  }
  // A configuration-dependent camera error: not one constant offset.
  const Eigen::Isometry3d d = camera_errors[0].inverse() * camera_errors[1];
  EXPECT_GT(d.translation().norm() + Eigen::AngleAxisd(d.linear()).angle(), 1e-3);
}

TEST(UrdfPerturbation, LinkLengthMovesTheJointAlongItsOrigin) {
  UrdfPerturbation p;
  p.origin_extension_m["left_arm_joint_2"] = 0.02;  // the upper arm grows by 2 cm
  const RobotModel nominal = model_of(test::kRobotUrdf), perturbed = model_of(perturb(p));
  for (const auto& q : configurations(5)) {
    const Eigen::Matrix3d R_root_upper = fk(nominal, q, "left_arm_upper").linear();
    const Eigen::Vector3d shift =
        fk(perturbed, q, "left_ee").translation() - fk(nominal, q, "left_ee").translation();
    EXPECT_LT((shift - R_root_upper * Eigen::Vector3d(0.02, 0, 0)).norm(), 1e-12);
  }
  p.origin_extension_m["left_arm_joint_2"] = -0.5;
  EXPECT_THROW(perturb(p), InputError);  // longer than the link
}

TEST(UrdfPerturbation, ShapeScaleScalesGeometryAboutTheLinkFrame) {
  UrdfPerturbation p;
  p.link_scale["left_arm_fore"] = 1.5;
  const RobotModel nominal = model_of(test::kRobotUrdf), perturbed = model_of(perturb(p));
  auto bounds = [](const RobotModel& m) {
    Eigen::AlignedBox3f box;
    for (const auto& v : m.link(m.link_index("left_arm_fore")).mesh.vertices_m) box.extend(v);
    return box;
  };
  const Eigen::AlignedBox3f a = bounds(nominal), b = bounds(perturbed);
  EXPECT_LT((a.min() - Eigen::Vector3f(0, -0.03f, -0.03f)).norm(), 1e-6);
  EXPECT_LT((b.min() - 1.5f * a.min()).norm(), 1e-6);
  EXPECT_LT((b.max() - 1.5f * a.max()).norm(), 1e-6);
  // The other arm is untouched.
  const int r = nominal.link_index("right_arm_fore");
  EXPECT_EQ(nominal.link(r).mesh.vertices_m, perturbed.link(r).mesh.vertices_m);
}

TEST(UrdfPerturbation, BadNamesAndValuesAreInputErrors) {
  UrdfPerturbation p;
  p.origin_extension_m["elbow"] = 0.01;
  EXPECT_THROW(perturb(p), InputError);
  p = {};
  p.origin_extension_m["head_pan_joint"] = 0.0;  // fine: zero change of a real joint
  EXPECT_NO_THROW(perturb(p));
  p = {};
  p.origin_extension_m["left_ee_joint"] = 0.01;
  EXPECT_NO_THROW(perturb(p));
  p = {};
  p.link_scale["left_arm_fore"] = -1;
  EXPECT_THROW(perturb(p), InputError);
  p = {};
  p.link_scale["hand"] = 2;
  EXPECT_THROW(perturb(p), InputError);
  p = {};
  p.camera_link = "base_link";  // the root has no parent joint
  p.T_nominal_true_camera.translation() << 0.01, 0, 0;
  expect_error_naming([&] { perturb(p); }, "base_link");
  JointOriginChange c;
  c.joint = "neck";
  p = {};
  p.joint_changes.push_back(c);
  EXPECT_THROW(perturb(p), InputError);
  EXPECT_THROW(perturb_urdf_text("<robot", "bad.urdf", ".", {}, {}), InputError);
}

// A robot whose link is a mesh given by a relative path: the perturbed copy
// in a temporary folder still finds it, MuJoCo builds it, and MuJoCo's camera
// sits at the nominal camera moved by the offset.
TEST(UrdfPerturbation, PerturbedCopyBuildsInMuJoCoWithTheOffsetCamera) {
  const test::TestDir dir("urdf_perturbation_mujoco");
  fs::create_directories(dir.path() / "meshes");
  dir.write("meshes/tri.obj",
            "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  std::string urdf = test::kRobotUrdf;
  const std::string box = R"(<geometry><box size="0.3 0.07 0.07"/></geometry>)";
  urdf.replace(urdf.find(box), box.size(),
               R"(<geometry><mesh filename="meshes/tri.obj"/></geometry>)");
  const fs::path file = dir.write("robot_mesh.urdf", urdf);

  UrdfPerturbation p;
  p.T_nominal_true_camera =
      pose({0.02, 0.01, -0.03}, rpy(-2 * kRadPerDeg, 1 * kRadPerDeg, 4 * kRadPerDeg));
  fs::path copy_dir;
  {
    const PerturbedUrdf copy(file, {}, p);
    copy_dir = copy.path().parent_path();
    EXPECT_NE(copy_dir, dir.path());
    std::stringstream text;
    text << std::ifstream(copy.path()).rdbuf();
    EXPECT_NE(text.str().find((dir.path() / "meshes/tri.obj").string()), std::string::npos);

    SceneDescription scene;
    scene.urdf_path = copy.path();
    scene.floor = false;
    scene.width = 32;
    scene.height = 24;
    scene.initial_joints_rad = {{"head_pan_joint", 0.3}, {"head_tilt_joint", 0.5}};
    const auto model = build_sim_model(scene);
    const Simulator sim(model);
    const Eigen::Isometry3d expected =
        fk(model_of(urdf, dir.path().string()), {{"head_pan_joint", 0.3}, {"head_tilt_joint", 0.5}},
           "camera_optical_frame") *
        p.T_nominal_true_camera;
    EXPECT_LT((sim.ground_truth().T_world_camera.matrix() - expected.matrix()).norm(), 1e-9);
  }
  EXPECT_FALSE(fs::exists(copy_dir));  // removed with the object
  std::stringstream original;
  original << std::ifstream(file).rdbuf();
  EXPECT_EQ(original.str(), urdf);  // the user's file is untouched
}

TEST(UrdfPerturbation, SummaryListsJointsAndLimits) {
  const test::TestDir dir("urdf_summary");
  const UrdfSummary s = read_urdf_summary(dir.path() / "robot.urdf");
  EXPECT_EQ(s.movable_joints,
            (std::vector<std::string>{"left_arm_joint_1", "left_arm_joint_2", "right_arm_joint_1",
                                      "right_arm_joint_2", "head_pan_joint", "head_tilt_joint"}));
  EXPECT_EQ(s.movable_limits[5].lower_rad, -1.0);
  EXPECT_EQ(s.movable_limits[5].upper_rad, 1.2);
  EXPECT_TRUE(s.has_joint("camera_joint"));
  EXPECT_TRUE(s.has_link("left_ee"));
  EXPECT_EQ(s.movable_index("head_pan_joint"), 4);
  EXPECT_THROW(read_urdf_summary(dir.path() / "missing.urdf"), InputError);
}

}  // namespace
}  // namespace arttrack::sim
