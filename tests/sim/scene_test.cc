// Scene YAML: every key read into the struct, paths resolved, and bad input
// (unknown key, wrong type, malformed YAML, missing file) an InputError
// naming the file and the key.
#include "arttrack/sim/scene.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "../error_of.h"
#include "../scratch_dir.h"
#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;

fs::path test_dir() { return test_support::program_scratch_dir().path(); }

using test_support::write_scratch_file;

constexpr char kUrdf[] = R"(<robot name="r"><link name="base_link"/></robot>)";

constexpr char kFullScene[] = R"(
robot:
  urdf: robot.urdf
  packages: {some_pkg: .}
  initial_joints_deg: {j1: 90, j2: -45}
  end_effectors: [tool]
camera:
  link: base_link
  width: 320
  height: 240
  fovy_deg: 60
  near_m: 0.2
  far_m: 4
  shape_segments: 64
actuators:
  kp: 100
  kv: 10
  joints: {j1: {kp: 50}}
  limit_to_urdf_effort: false
  armature_kg_m2: 0.02
physics:
  timestep_s: 0.001
  gravity_m_s2: [0, 0, -9.8]
  extent_m: 2.5
floor: false
table: {position_m: [0.7, 0.1], height_m: 0.7, top_size_m: [0.6, 1.0, 0.03]}
objects:
  - {name: mug, type: cylinder, radius_m: 0.04, length_m: 0.1, position_m: [0.6, 0, 0.75]}
  - {name: crate, type: box, size_m: [0.1, 0.2, 0.3], position_m: [0.7, 0.2, 0.85], rpy_deg: [0, 0, 90], free: true}
lights:
  - {position_m: [0, 0, 3], direction: [0, 0, -1], directional: true}
occluders:
  - {name: board, type: box, size_m: [0.02, 0.5, 0.5], position_m: [3, 0, 0]}
  - {name: visitor, type: person, height_m: 1.8, position_m: [2, 1, 0], rpy_deg: [0, 0, 180]}
)";

TEST(Scene, ReadsEveryKey) {
  write_scratch_file("robot.urdf", kUrdf);
  const SceneDescription s = load_scene(write_scratch_file("full.yaml", kFullScene));
  EXPECT_EQ(s.urdf_path, fs::weakly_canonical(test_dir() / "robot.urdf"));
  EXPECT_EQ(s.package_paths.at("some_pkg"), fs::weakly_canonical(test_dir()));
  EXPECT_NEAR(s.initial_joints_rad.at("j1"), M_PI / 2, 1e-15);
  EXPECT_NEAR(s.initial_joints_rad.at("j2"), -M_PI / 4, 1e-15);
  EXPECT_EQ(s.end_effector_links, std::vector<std::string>{"tool"});
  EXPECT_EQ(s.camera_link, "base_link");
  EXPECT_EQ(s.width, 320);
  EXPECT_EQ(s.height, 240);
  EXPECT_NEAR(s.fovy_rad, M_PI / 3, 1e-15);
  EXPECT_EQ(s.near_m, 0.2);
  EXPECT_EQ(s.far_m, 4);
  EXPECT_EQ(s.shape_segments, 64);
  EXPECT_EQ(s.default_gains.kp_Nm_per_rad, 100);
  EXPECT_EQ(s.joint_gains.at("j1").kp_Nm_per_rad, 50);
  EXPECT_EQ(s.joint_gains.at("j1").kv_Nms_per_rad, 10);  // inherits the default
  EXPECT_FALSE(s.limit_torque_to_urdf_effort);
  EXPECT_EQ(s.armature_kg_m2, 0.02);
  EXPECT_EQ(s.timestep_s, 0.001);
  EXPECT_EQ(s.gravity_m_s2.z(), -9.8);
  EXPECT_EQ(s.extent_m, 2.5);
  EXPECT_FALSE(s.floor);
  ASSERT_EQ(s.shapes.size(), 7u);  // table top, 4 legs, 2 objects
  EXPECT_EQ(s.shapes[0].name, "table_top");
  // The top's upper face is at the table height.
  EXPECT_NEAR(s.shapes[0].T_world_shape.translation().z() + 0.5 * s.shapes[0].size_m.z(), 0.7,
              1e-12);
  EXPECT_EQ(s.shapes[5].type, SceneShape::Type::kCylinder);
  EXPECT_EQ(s.shapes[5].size_m[0], 0.04);
  EXPECT_TRUE(s.shapes[6].free);
  EXPECT_NEAR((s.shapes[6].T_world_shape.linear() * Eigen::Vector3d::UnitX()).y(), 1, 1e-12);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_TRUE(s.lights[0].directional);
  ASSERT_EQ(s.occluders.size(), 2u);
  EXPECT_EQ(s.occluders[1].type, OccluderSpec::Type::kPerson);
  EXPECT_EQ(s.occluders[1].size_m[0], 1.8);
}

TEST(Scene, DefaultSceneLoads) {
  const SceneDescription s = load_scene(default_scene_path());
  EXPECT_TRUE(fs::exists(s.urdf_path));
  EXPECT_FALSE(s.initial_joints_rad.empty());
  EXPECT_FALSE(s.shapes.empty());
}

// The robot's home pose is documented in the header comment of
// models/dual_arm.urdf ("  name   <degrees> = <radians>" lines, written by
// models/generate_robot.py); the default scene must start there.
TEST(Scene, DefaultSceneStartsAtTheDocumentedHome) {
  const SceneDescription s = load_scene(default_scene_path());
  std::ifstream in(s.urdf_path);
  std::map<std::string, double> documented;
  for (std::string line; std::getline(in, line) && line.find("<robot") == std::string::npos;) {
    std::istringstream words(line);
    std::string name, equals;
    double deg, rad;
    if (words >> name >> deg >> equals >> rad && equals == "=") documented[name] = rad;
  }
  ASSERT_GE(documented.size(), 16u);
  EXPECT_EQ(documented.size(), s.initial_joints_rad.size());
  for (const auto& [name, rad] : documented) {
    ASSERT_TRUE(s.initial_joints_rad.count(name)) << name;
    EXPECT_NEAR(s.initial_joints_rad.at(name), rad, 1e-6) << name;
  }
}

std::string load_error(const std::string& name, const std::string& text) {
  return test_support::error_of([&] { load_scene(write_scratch_file(name, text)); });
}

void expect_error(const std::string& name, const std::string& text,
                  const std::vector<std::string>& parts) {
  const std::string e = load_error(name, text);
  ASSERT_FALSE(e.empty()) << name << " loaded without error";
  EXPECT_NE(e.find(name), std::string::npos) << e;
  for (const auto& p : parts) EXPECT_NE(e.find(p), std::string::npos) << e;
}

TEST(Scene, BadInputNamesFileAndKey) {
  write_scratch_file("robot.urdf", kUrdf);
  expect_error("unknown_key.yaml", "robot: {urdf: robot.urdf}\ncamera: {fov_deg: 50}\n",
               {"camera.fov_deg"});
  expect_error("unknown_top.yaml", "robot: {urdf: robot.urdf}\nlighting: []\n", {"lighting"});
  expect_error("wrong_type.yaml", "robot: {urdf: robot.urdf}\ncamera: {width: wide}\n",
               {"camera.width"});
  expect_error("malformed.yaml", "robot: {urdf: robot.urdf\ncamera: [\n", {"malformed"});
  expect_error("no_robot.yaml", "camera: {width: 64}\n", {"robot"});
  expect_error("missing_urdf.yaml", "robot: {urdf: nowhere.urdf}\n",
               {"robot.urdf", "nowhere.urdf"});
  expect_error(
      "bad_vector.yaml",
      "robot: {urdf: robot.urdf}\nobjects: [{name: a, size_m: [1, 2], position_m: [0, 0, 0]}]\n",
      {"objects[0].size_m"});
  expect_error("bad_choice.yaml",
               "robot: {urdf: robot.urdf}\noccluders: [{name: a, type: tree, size_m: [1, 1, 1]}]\n",
               {"occluders[0].type", "tree"});
  expect_error(
      "both_units.yaml",
      "robot: {urdf: robot.urdf, initial_joints_deg: {a: 1}, initial_joints_rad: {a: 1}}\n",
      {"initial_joints_rad"});
  expect_error("far_near.yaml", "robot: {urdf: robot.urdf}\ncamera: {near_m: 2, far_m: 1}\n",
               {"camera.far_m"});
  expect_error(
      "unknown_object_key.yaml",
      "robot: {urdf: robot.urdf}\nobjects: [{name: a, radius_m: 1, type: sphere, colour: red}]\n",
      {"objects[0].colour"});
}

TEST(Scene, MissingFile) {
  const std::string path = (test_dir() / "does_not_exist.yaml").string();
  try {
    load_scene(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does_not_exist.yaml"), std::string::npos);
  }
}

}  // namespace
}  // namespace arttrack::sim
