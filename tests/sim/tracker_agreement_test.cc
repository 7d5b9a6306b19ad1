// The tracker's robot model against MuJoCo, an independent implementation:
// forward kinematics must agree with MuJoCo's body poses, and the tracker's
// CPU depth render with MuJoCo's OpenGL depth of the robot alone. Run on the
// real robot (primitive and mesh variants: the mesh variant also proves the
// DAE/OBJ/STL conversion), on a small inline robot and on a description
// with what ROS tolerates (tests/sim/data/irregular_description).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "../scratch_dir.h"
#include "arttrack/sim/depth_camera.h"
#include "arttrack/sim/depth_compare.h"
#include "arttrack/sim/scene.h"
#include "arttrack/sim/simulator.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/tracker_config.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;

// A pan-tilt head with a camera looking down at a three-joint arm; boxes,
// cylinders and spheres, joints listed out of tree order.
constexpr char kInlineRobot[] = R"(<robot name="inline">
  <link name="base_link">
    <visual><origin xyz="0 0 0.1"/><geometry><box size="0.3 0.3 0.2"/></geometry></visual>
  </link>
  <joint name="wrist" type="revolute"><parent link="forearm"/><child link="hand"/>
    <origin xyz="0.3 0 0"/><axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upperarm"/><child link="forearm"/>
    <origin xyz="0 0 0.3" rpy="0 1.5707963267948966 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <joint name="shoulder" type="continuous"><parent link="base_link"/><child link="upperarm"/>
    <origin xyz="0.35 0 0.5"/><axis xyz="0 0 1"/></joint>
  <link name="upperarm"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.04" length="0.3"/></geometry></visual></link>
  <link name="forearm"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0.15 0 0" rpy="0.3 0 0"/><geometry><box size="0.3 0.06 0.08"/></geometry></visual></link>
  <link name="hand"><inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0.05 0 0"/><geometry><sphere radius="0.05"/></geometry></visual></link>
  <joint name="head_pan_joint" type="revolute"><parent link="base_link"/><child link="head_pan_link"/>
    <origin xyz="0 0 1.1"/><axis xyz="0 0 1"/><limit lower="-0.5" upper="0.5" effort="10" velocity="1"/></joint>
  <link name="head_pan_link"><inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="head_tilt_joint" type="revolute"><parent link="head_pan_link"/><child link="head_tilt_link"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="0.6" upper="0.9" effort="10" velocity="1"/></joint>
  <link name="head_tilt_link"><inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="camera_joint" type="fixed"><parent link="head_tilt_link"/><child link="camera_optical_frame"/>
    <origin xyz="0.05 0 0.03" rpy="-1.5707963267948966 0 -1.5707963267948966"/></joint>
  <link name="camera_optical_frame"/>
</robot>)";

struct Robot {
  const char* name;
  fs::path urdf;
  std::map<std::string, fs::path> packages;
};

Robot inline_robot() {
  return {"inline", test_support::write_scratch_file("inline.urdf", kInlineRobot), {}};
}

const fs::path kModels = fs::path(ARTTRACK_SOURCE_DIR) / "models";
Robot dual_arm() { return {"dual_arm", kModels / "dual_arm.urdf", {{"arttrack_models", kModels}}}; }
Robot dual_arm_meshes() {
  return {"dual_arm_meshes", kModels / "dual_arm_meshes.urdf", {{"arttrack_models", kModels}}};
}

// What ROS tolerates and MuJoCo 2.2 refuses or reads otherwise (repeated
// elements, a missing <origin>, package:// found through package.xml, a
// material by name only, Gazebo and transmission elements, a scaled mesh, a
// massless moving link, ...: the file lists them).
Robot irregular() {
  return {
      "irregular",
      fs::path(ARTTRACK_SOURCE_DIR) / "tests/sim/data/irregular_description/urdf/irregular.urdf",
      {}};
}

SceneDescription scene_for(const Robot& r, int width, int height) {
  SceneDescription s;
  s.urdf_path = r.urdf;
  s.package_paths = r.packages;
  s.end_effector_links = {};
  s.floor = false;
  s.width = width;
  s.height = height;
  s.fovy_rad = 58.0 * M_PI / 180.0;
  s.near_m = 0.05;
  s.far_m = 6.0;
  return s;
}

// The comparison is of geometry, kinematics and camera, not tessellation:
// both sides draw cylinders and spheres finely (the tracker's default
// 16-segment sphere is up to 15 mm off a true 10 cm sphere; MuJoCo's scene
// draws 48 x 24 by default).
RobotModel tracker_model(const Robot& r) {
  RobotModelOptions o;
  o.add_virtual_camera_joints = false;
  o.cylinder_segments = 64;
  o.sphere_segments = 64;
  for (const auto& [name, dir] : r.packages) o.mesh_search_paths.push_back(dir);
  return RobotModel::from_urdf_file(r.urdf.string(), o);
}

// Tracker q (its own DOF order) for simulator joint values, by name.
Eigen::VectorXd to_tracker(const RobotModel& robot, const SimModel& sim, const Eigen::VectorXd& q) {
  Eigen::VectorXd out(robot.num_joints());
  for (int i = 0; i < robot.num_joints(); ++i) {
    const int j = sim.joint_index(robot.joint_name(i));
    EXPECT_GE(j, 0) << robot.joint_name(i);
    out[i] = j >= 0 ? q[j] : 0.0;
  }
  return out;
}

// Uniform within limits; continuous joints in [-pi, pi].
Eigen::VectorXd random_q(const SimModel& m, std::mt19937& rng) {
  Eigen::VectorXd q(m.joint_names.size());
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const double lo = std::isfinite(m.joint_lower[i]) ? m.joint_lower[i] : -M_PI;
    const double hi = std::isfinite(m.joint_upper[i]) ? m.joint_upper[i] : M_PI;
    q[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

void check_kinematics(const Robot& r) {
  SCOPED_TRACE(r.name);
  const auto model = build_sim_model(scene_for(r, 64, 48));
  const RobotModel robot = tracker_model(r);
  ASSERT_EQ(robot.num_joints(), int(model->joint_names.size()));
  Simulator sim(model);
  KinematicsState state(robot);
  std::mt19937 rng(2017);
  double worst_m = 0, worst_rad = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::VectorXd q = random_q(*model, rng);
    sim.set_joint_positions(q);  // mj_forward: MuJoCo's kinematics
    forward_kinematics(robot, to_tracker(robot, *model, q), state);
    const GroundTruth truth = sim.ground_truth();
    for (size_t l = 0; l < model->link_names.size(); ++l) {
      const Eigen::Isometry3d& T_mj = truth.T_world_link[l];
      const Eigen::Isometry3d& T_tr = state.T_root_link[robot.link_index(model->link_names[l])];
      worst_m = std::max(worst_m, (T_mj.translation() - T_tr.translation()).norm());
      worst_rad =
          std::max(worst_rad, Eigen::AngleAxisd(T_mj.linear().transpose() * T_tr.linear()).angle());
    }
  }
  std::printf("%s: 100 configurations, worst link error %.2e m, %.2e rad\n", r.name, worst_m,
              worst_rad);
  EXPECT_LT(worst_m, 1e-9);
  EXPECT_LT(worst_rad, 1e-9);
}

TEST(TrackerAgreement, KinematicsInlineRobot) { check_kinematics(inline_robot()); }
TEST(TrackerAgreement, KinematicsDualArm) { check_kinematics(dual_arm()); }
TEST(TrackerAgreement, KinematicsDualArmMeshes) { check_kinematics(dual_arm_meshes()); }
TEST(TrackerAgreement, KinematicsIrregularDescription) { check_kinematics(irregular()); }

// The scene's initial pose first, then poses around it: each joint moved by
// a normal random angle of sigma_rad and clamped to its limits.
class PosesAroundHome {
 public:
  PosesAroundHome(const SimModel& model, unsigned seed, double sigma_rad)
      : model_(model), rng_(seed), perturb_(0, sigma_rad) {}

  Eigen::VectorXd next() {
    Eigen::VectorXd q = model_.initial_joints;
    if (first_) {
      first_ = false;
      return q;
    }
    for (Eigen::Index i = 0; i < q.size(); ++i)
      q[i] = std::clamp(q[i] + perturb_(rng_), model_.joint_lower[i], model_.joint_upper[i]);
    return q;
  }

 private:
  const SimModel& model_;
  std::mt19937 rng_;
  std::normal_distribution<double> perturb_;
  bool first_ = true;
};

// MuJoCo's depth of the robot alone and the tracker's render of it, drawn for
// one pose at a time (simulator joint order) and compared within 2 mm.
class BothRenders {
 public:
  BothRenders(std::shared_ptr<const SimModel> model, const RobotModel& robot,
              const RenderOptions& options = {})
      : model_(model),
        robot_(robot),
        sim_(model),
        camera_(model),
        renderer_(robot, camera_.intrinsics(), options),
        state_(robot) {}

  DepthAgreement compare(const Eigen::VectorXd& q) {
    sim_.set_joint_positions(q);
    camera_.render(sim_.data(), DepthContent::kRobot, mujoco);
    forward_kinematics(robot_, to_tracker(robot_, *model_, q), state_);
    renderer_.render(state_, tracker);
    return compare_depth(tracker, mujoco, 2e-3);
  }

  DepthImage mujoco, tracker;  // of the last pose compared

 private:
  std::shared_ptr<const SimModel> model_;
  const RobotModel& robot_;
  Simulator sim_;
  DepthCamera camera_;
  DepthRenderer renderer_;
  KinematicsState state_;
};

// Renders at 160x120 for the scene's initial pose (if any) and perturbed
// poses around it, and compares the tracker's render with MuJoCo's. With
// `geometry`, the tracker's meshes are simplified as a tracker with that
// configuration draws them for an 80x60 likelihood (mesh_simplify.h).
void check_render(const Robot& r, const std::map<std::string, double>& home,
                  const TrackerConfig::Geometry* geometry = nullptr,
                  bool open_parts_both_sides = false) {
  SCOPED_TRACE(r.name);
  SceneDescription scene = scene_for(r, 160, 120);
  scene.initial_joints_rad = home;
  const auto model = build_sim_model(scene);
  RobotModel robot = tracker_model(r);
  double bound_m = 0;
  if (geometry) {
    const CameraIntrinsics likelihood = CameraIntrinsics::from_vertical_fov(80, 60, scene.fovy_rad);
    const int full = robot.num_drawn_triangles();
    bound_m = geometry->error_bound_m(likelihood);
    robot = robot.with_simplified_meshes(bound_m, nullptr, geometry->nearest_range_m,
                                         geometry->coarser_levels);
    std::printf("%s: %d triangles drawn of %d\n", r.name, robot.num_drawn_triangles(), full);
    EXPECT_LT(robot.num_drawn_triangles(), full);
  }
  RenderOptions options;
  options.near_m = float(scene.near_m);  // clip where MuJoCo clips
  options.open_parts_both_sides = open_parts_both_sides;
  BothRenders renders(model, robot, options);
  PosesAroundHome poses(*model, 30, 0.15);
  for (int trial = 0; trial < 6; ++trial) {
    const DepthAgreement a = renders.compare(poses.next());
    std::printf("%s configuration %d: %s\n", r.name, trial, a.summary().c_str());
    SCOPED_TRACE("configuration " + std::to_string(trial) + ": " + a.summary());
    EXPECT_GT(a.pixels_both, 300);  // the robot is in view
    EXPECT_GE(a.silhouette_iou(), 0.98);
    if (!geometry) {
      EXPECT_GE(a.fraction_within(), 0.99);
      continue;
    }
    // Simplified: within 2 mm plus the bound of the level drawn there (the
    // bound times the depth over the nearest range, levels of detail).
    int both = 0, within = 0;
    for (std::size_t i = 0; i < renders.tracker.depth_m.size(); ++i) {
      const double t = renders.tracker.depth_m[i], m = renders.mujoco.depth_m[i];
      if (!(t > 0 && m > 0)) continue;
      ++both;
      within += std::abs(t - m) <= 2e-3 + bound_m * std::max(1.0, t / geometry->nearest_range_m);
    }
    EXPECT_GE(double(within) / both, 0.99) << within << " of " << both;
  }
}

// The home pose of the default scene.
std::map<std::string, double> home_pose() {
  return load_scene(default_scene_path()).initial_joints_rad;
}

TEST(TrackerAgreement, RenderDualArm) { check_render(dual_arm(), home_pose()); }
TEST(TrackerAgreement, RenderDualArmMeshes) {
  // The mesh variant reaches MuJoCo as meshes (converted from DAE, OBJ, STL).
  const auto model = build_sim_model(scene_for(dual_arm_meshes(), 64, 48));
  EXPECT_GE(model->mj->nmesh, 4);
  check_render(dual_arm_meshes(), home_pose());
}
// As the tracker draws it by default: its meshes simplified for an 80x60
// likelihood (TrackerConfig::geometry), within the same bounds.
TEST(TrackerAgreement, RenderDualArmMeshesSimplified) {
  const TrackerConfig::Geometry defaults = default_tracker_config().geometry;
  check_render(dual_arm_meshes(), home_pose(), &defaults);
}
// The sculpted dual arm (models/generate_sculpted.py, 330 000 triangles), as
// the tracker draws it by default, levels of detail included.
TEST(TrackerAgreement, RenderSculptedDualArmSimplified) {
  const TrackerConfig::Geometry defaults = default_tracker_config().geometry;
  check_render(
      {"dual_arm_sculpted", kModels / "dual_arm_sculpted.urdf", {{"arttrack_models", kModels}}},
      home_pose(), &defaults);
}

// What the tracker really uses: its default tessellation, the default scene
// and camera, at 160x120, home pose and perturbations of it.
TEST(TrackerAgreement, RenderDefaultSceneWithTheTrackersDefaults) {
  SceneDescription scene = load_scene(default_scene_path());
  scene.width = 160;
  scene.height = 120;
  const auto model = build_sim_model(scene);
  RobotModelOptions options;  // defaults, less the (zero) virtual camera joints
  options.add_virtual_camera_joints = false;
  const RobotModel robot = RobotModel::from_urdf_file(scene.urdf_path.string(), options);
  BothRenders renders(model, robot);
  PosesAroundHome poses(*model, 7, 0.1);
  for (int trial = 0; trial < 4; ++trial) {
    const DepthAgreement a = renders.compare(poses.next());
    std::printf("default scene configuration %d: %s\n", trial, a.summary().c_str());
    SCOPED_TRACE("configuration " + std::to_string(trial) + ": " + a.summary());
    EXPECT_GT(a.pixels_both, 2000);
    EXPECT_GE(a.fraction_within(), 0.99);
    EXPECT_GE(a.silhouette_iou(), 0.98);
  }
}

// The tracker (urdfdom) and the simulator read the first of each repeated
// element alike: the same shapes in the same places.
TEST(TrackerAgreement, RenderIrregularDescription) { check_render(irregular(), {{"elbow", 0.3}}); }

TEST(TrackerAgreement, RenderInlineRobot) {
  check_render(inline_robot(), {{"shoulder", 0.3}, {"elbow", 0.4}, {"head_tilt_joint", 0.75}});
}

// The mesh dual arm copied with its meshes as makers sometimes export them:
// forearm.stl wound inside out, and (`open`) upper_arm.obj with a face
// missing. A camera sees the same surfaces whichever way they are wound.
Robot dual_arm_meshes_as_exported(const fs::path& dir, bool open) {
  fs::copy(kModels / "dual_arm_meshes.urdf", dir / "dual_arm_meshes.urdf");
  fs::copy(kModels / "meshes", dir / "meshes", fs::copy_options::recursive);
  {  // binary STL: swap two corners of every facet
    const fs::path stl = dir / "meshes" / "forearm.stl";
    std::ifstream in(stl, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    EXPECT_EQ((bytes.size() - 84) % 50, 0u);
    for (std::size_t at = 84; at + 50 <= bytes.size(); at += 50)
      std::swap_ranges(bytes.begin() + long(at + 24), bytes.begin() + long(at + 36),
                       bytes.begin() + long(at + 36));
    std::ofstream(stl, std::ios::binary) << bytes;
  }
  if (open) {  // drop the last face
    const fs::path obj = dir / "meshes" / "upper_arm.obj";
    std::ifstream in(obj);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    const std::size_t last = text.rfind("\nf ");
    EXPECT_NE(last, std::string::npos);
    text.erase(last + 1, text.find('\n', last + 1) - last);
    std::ofstream(obj) << text;
  }
  return {"dual_arm_meshes_as_exported", dir / "dual_arm_meshes.urdf", {{"arttrack_models", dir}}};
}

// Inside out: the simulator and the tracker both turn the forearms outward,
// so MuJoCo's depth is the original robot's (it culls back faces: without
// the turn it drew the forearm's far side) and the tracker agrees with it.
TEST(TrackerAgreement, RenderMeshesWoundInsideOut) {
  const test_support::ScratchDir dir("agreement_inside_out");
  const Robot exported = dual_arm_meshes_as_exported(dir.path(), /*open=*/false);
  const RobotModel robot = tracker_model(exported);
  for (const char* link : {"left_arm_link_5", "right_arm_link_5"})  // the forearms
    EXPECT_GE(robot.link(robot.link_index(link)).mesh_parts.turned_parts, 1)
        << describe_mesh_parts(robot);
  check_render(exported, home_pose());

  SceneDescription scene = scene_for(exported, 160, 120);
  scene.initial_joints_rad = home_pose();
  const auto turned = build_sim_model(scene);
  EXPECT_FALSE(turned->render_both_sides);
  scene.urdf_path = dual_arm_meshes().urdf;
  scene.package_paths = dual_arm_meshes().packages;
  const auto original = build_sim_model(scene);
  Simulator sim_turned(turned), sim_original(original);
  DepthCamera camera_turned(turned), camera_original(original);
  DepthImage depth_turned, depth_original;
  PosesAroundHome poses(*original, 31, 0.15);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd q = poses.next();
    sim_turned.set_joint_positions(q);
    sim_original.set_joint_positions(q);
    camera_turned.render(sim_turned.data(), DepthContent::kRobot, depth_turned);
    camera_original.render(sim_original.data(), DepthContent::kRobot, depth_original);
    const DepthAgreement a = compare_depth(depth_turned, depth_original, 1e-4);
    EXPECT_GE(a.fraction_within(), 0.999) << a.summary();
  }
}

// Open: MuJoCo's camera draws both sides of every surface, and so does the
// tracker asked to draw open parts from both sides; they agree.
TEST(TrackerAgreement, RenderMeshesWithAnOpenPart) {
  const test_support::ScratchDir dir("agreement_open");
  const Robot exported = dual_arm_meshes_as_exported(dir.path(), /*open=*/true);
  const RobotModel robot = tracker_model(exported);
  int open_links = 0;
  for (int l = 0; l < robot.num_links(); ++l) open_links += robot.link(l).has_open_parts();
  EXPECT_EQ(open_links, 2) << describe_mesh_parts(robot);  // the upper arms
  SceneDescription scene = scene_for(exported, 160, 120);
  EXPECT_TRUE(build_sim_model(scene)->render_both_sides);
  EXPECT_FALSE(build_sim_model(scene_for(dual_arm_meshes(), 64, 48))->render_both_sides);
  check_render(exported, home_pose(), nullptr, /*open_parts_both_sides=*/true);
}

}  // namespace
}  // namespace arttrack::sim
