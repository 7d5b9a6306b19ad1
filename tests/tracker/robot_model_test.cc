#include "arttrack/tracker/robot_model.h"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>

#include "../error_of.h"
#include "../test_files.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/model_limits.h"

namespace arttrack {
namespace {

using arttrack::test_support::error_of;

namespace fs = std::filesystem;

using test_support::fresh_test_dir;
using test_support::kUnitCubeObj;
using test_support::write_file;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A branching tree: base -> arm (revolute, then a prismatic and a fixed
// joint) and base -> head (continuous) -> camera (fixed).
constexpr char kTree[] = R"(<robot name="tree">
  <link name="base_link"><visual><geometry><box size="0.2 0.2 0.2"/></geometry></visual></link>
  <link name="upper"><visual><geometry><cylinder radius="0.05" length="0.3"/></geometry></visual></link>
  <link name="slider"/>
  <link name="tool"><visual><geometry><sphere radius="0.03"/></geometry></visual></link>
  <link name="head"/>
  <link name="camera_optical_frame"/>
  <joint name="b_shoulder" type="revolute">
    <parent link="base_link"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="2.0" effort="1" velocity="1"/>
  </joint>
  <joint name="b_slide" type="prismatic">
    <parent link="upper"/><child link="slider"/><origin xyz="0 0 0.3"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.2" effort="1" velocity="1"/>
  </joint>
  <joint name="b_tool_mount" type="fixed"><parent link="slider"/><child link="tool"/></joint>
  <joint name="a_head_pan" type="continuous">
    <parent link="base_link"/><child link="head"/><origin xyz="0 0 0.5"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="a_camera_mount" type="fixed">
    <parent link="head"/><child link="camera_optical_frame"/><origin xyz="0.1 0 0" rpy="-1.5708 0 -1.5708"/>
  </joint>
</robot>
)";

TEST(RobotModel, TreeOrderDofsLimitsAndVirtualJoints) {
  const RobotModel model = RobotModel::from_urdf_string(kTree, "");
  // 6 URDF links + 6 virtual frames; 3 URDF DOFs + 6 virtual.
  EXPECT_EQ(model.num_links(), 12);
  ASSERT_EQ(model.num_joints(), 9);
  // Depth-first, siblings by joint name: the a_ branch before the b_ branch.
  const std::vector<std::string> expected = {
      "a_head_pan",         "b_shoulder",          "b_slide",
      "camera_offset_x",    "camera_offset_y",     "camera_offset_z",
      "camera_offset_roll", "camera_offset_pitch", "camera_offset_yaw"};
  EXPECT_EQ(model.joint_names(), expected);
  for (int l = 1; l < model.num_links(); ++l) EXPECT_LT(model.link(l).parent, l);
  EXPECT_EQ(model.link_name(0), "base_link");

  const int shoulder = model.joint_index("b_shoulder");
  EXPECT_EQ(model.joint_type(shoulder), JointType::kRevolute);
  EXPECT_EQ(model.joint_lower(shoulder), -1.5);
  EXPECT_EQ(model.joint_upper(shoulder), 2.0);
  EXPECT_EQ(model.link_name(model.joint_child_link(shoulder)), "upper");
  const int pan = model.joint_index("a_head_pan");
  EXPECT_TRUE(std::isinf(model.joint_upper(pan)));
  EXPECT_FALSE(model.is_virtual_joint(pan));
  EXPECT_TRUE(model.is_virtual_joint(model.joint_index("camera_offset_yaw")));
  EXPECT_EQ(model.joint_type(model.joint_index("camera_offset_z")), JointType::kPrismatic);
  EXPECT_EQ(model.joint_type(model.joint_index("camera_offset_roll")), JointType::kRevolute);

  EXPECT_EQ(model.link_name(model.nominal_camera_link()), "camera_optical_frame");
  EXPECT_EQ(model.link_name(model.camera_link()), "camera_optical_frame_corrected");

  // The shoulder moves its whole subtree and nothing else.
  const LinkSet moved = model.links_moved_by(shoulder);
  for (int l = 0; l < model.num_links(); ++l) {
    const std::string& name = model.link_name(l);
    EXPECT_EQ(bool(moved[l]), name == "upper" || name == "slider" || name == "tool") << name;
  }
  // Below the shoulder's child link: the same subtree; below the tool: itself.
  EXPECT_EQ(model.links_below(model.link_index("upper")), moved);
  const LinkSet tool = model.links_below(model.link_index("tool"));
  for (int l = 0; l < model.num_links(); ++l)
    EXPECT_EQ(bool(tool[l]), model.link_name(l) == "tool") << model.link_name(l);
  // Links with geometry: base, upper, tool.
  EXPECT_EQ(model.links_with_geometry().size(), 3u);
}

TEST(RobotModel, WithoutVirtualJointsTheCameraIsTheNominalFrame) {
  RobotModelOptions options;
  options.add_virtual_camera_joints = false;
  const RobotModel model = RobotModel::from_urdf_string(kTree, "", options);
  EXPECT_EQ(model.num_joints(), 3);
  EXPECT_EQ(model.camera_link(), model.nominal_camera_link());
}

TEST(RobotModel, LookupErrorsNameTheItemAndTheFile) {
  const fs::path path = fresh_test_dir() / "tree.urdf";
  write_file(path, kTree);
  const RobotModel model = RobotModel::from_urdf_file(path.string());
  std::string msg = error_of([&] { model.joint_index("elbow"); });
  EXPECT_TRUE(contains(msg, "'elbow'") && contains(msg, path.string())) << msg;
  msg = error_of([&] { model.joint_index("b_tool_mount"); });
  EXPECT_TRUE(contains(msg, "'b_tool_mount'") && contains(msg, "fixed")) << msg;
  msg = error_of([&] { model.link_index("gripper"); });
  EXPECT_TRUE(contains(msg, "'gripper'") && contains(msg, path.string())) << msg;
  EXPECT_EQ(model.link_name(model.link_index("tool")), "tool");
}

TEST(RobotModel, FileErrorsNameTheFile) {
  const fs::path dir = fresh_test_dir();
  std::string msg = error_of([&] { RobotModel::from_urdf_file((dir / "absent.urdf").string()); });
  EXPECT_TRUE(contains(msg, "absent.urdf")) << msg;

  write_file(dir / "broken.urdf", "<robot name=\"x\"><link name=\"a\"></robot");
  msg = error_of([&] { RobotModel::from_urdf_file((dir / "broken.urdf").string()); });
  EXPECT_TRUE(contains(msg, "broken.urdf")) << msg;
}

constexpr char kJointTemplate[] = R"(<robot name="j">
  <link name="base_link"/><link name="camera_optical_frame"/>
  <joint name="odd_joint" type="TYPE">
    <parent link="base_link"/><child link="camera_optical_frame"/><axis xyz="AXIS"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
)";

std::string joint_urdf(const std::string& type, const std::string& axis = "0 0 1") {
  std::string text = kJointTemplate;
  text.replace(text.find("TYPE"), 4, type);
  text.replace(text.find("AXIS"), 4, axis);
  return text;
}

TEST(RobotModel, UnsupportedJointTypesNameTheJointAndFile) {
  const fs::path dir = fresh_test_dir();
  for (const std::string type : {"ball", "floating", "planar"}) {
    const fs::path path = dir / (type + ".urdf");
    write_file(path, joint_urdf(type));
    const std::string msg = error_of([&] { RobotModel::from_urdf_file(path.string()); });
    EXPECT_TRUE(contains(msg, "odd_joint") && contains(msg, path.string())) << type << ": " << msg;
  }
  const std::string msg =
      error_of([&] { RobotModel::from_urdf_string(joint_urdf("revolute", "0 0 0"), ""); });
  EXPECT_TRUE(contains(msg, "odd_joint") && contains(msg, "axis")) << msg;
  EXPECT_NO_THROW(RobotModel::from_urdf_string(joint_urdf("revolute"), ""));
}

// Link 'upper' is the child of two joints: base_link -> upper -> fore ->
// upper is a kinematic loop, which a tree walk would follow forever.
constexpr char kLoop[] = R"(<robot name="loop">
  <link name="base_link"/><link name="upper"/><link name="fore"/>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="upper"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="wrist" type="fixed"><parent link="fore"/><child link="upper"/></joint>
</robot>
)";

TEST(RobotModel, KinematicLoopNamesTheLinkAndBothJoints) {
  const fs::path path = fresh_test_dir() / "loop.urdf";
  write_file(path, kLoop);
  const std::string msg = error_of([&] { RobotModel::from_urdf_file(path.string()); });
  EXPECT_TRUE(contains(msg, path.string()) && contains(msg, "link 'upper'") &&
              contains(msg, "'shoulder'") && contains(msg, "'wrist'"))
      << msg;
}

// Geometry the simulator rejects is refused here too, naming the file, the
// link or joint and what would be right.
TEST(RobotModel, GeometryTheSimulatorRejectsIsRefused) {
  const fs::path dir = fresh_test_dir();
  auto load = [&](const std::string& name, const std::string& geometry,
                  const std::string& limit = R"(lower="-1" upper="1")") {
    const fs::path path = dir / (name + ".urdf");
    write_file(path, R"(<robot name="r"><link name="base_link"/>
  <link name="camera_optical_frame"/>
  <joint name="mount" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/></joint>
  <link name="arm"><visual><geometry>)" +
                         geometry +
                         R"(</geometry></visual></link>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit )" +
                         limit + R"( effort="1" velocity="1"/></joint>
</robot>)");
    return std::make_pair(path.string(),
                          error_of([&] { RobotModel::from_urdf_file(path.string()); }));
  };
  for (const auto& [name, geometry, expected] : std::vector<std::array<std::string, 3>>{
           {"negative_radius", R"(<sphere radius="-0.1"/>)", "sphere radius has -0.1"},
           {"zero_box", R"(<box size="0.1 0 0.1"/>)", "box size has 0"},
           {"zero_cylinder", R"(<cylinder radius="0.1" length="0"/>)", "cylinder radius"}}) {
    const auto [path, msg] = load(name, geometry);
    EXPECT_TRUE(contains(msg, path) && contains(msg, "link 'arm'") && contains(msg, expected) &&
                contains(msg, "expected positive"))
        << name << ": " << msg;
  }
  const auto [path, msg] =
      load("inverted", R"(<box size="0.1 0.1 0.1"/>)", R"(lower="1" upper="-1")");
  EXPECT_TRUE(contains(msg, path) && contains(msg, "joint 'shoulder'") &&
              contains(msg, "lower 1 > upper -1") && contains(msg, "lower <= upper"))
      << msg;
  EXPECT_EQ(load("fine", R"(<box size="0.1 0.1 0.1"/>)").second, "");

  // A mesh with a NaN vertex.
  write_file(dir / "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  const auto [mesh_path, mesh_msg] = load("nan_mesh", R"(<mesh filename="nan.obj"/>)");
  EXPECT_TRUE(contains(mesh_msg, "not finite") && contains(mesh_msg, "'arm'") &&
              contains(mesh_msg, mesh_path))
      << mesh_msg;
}

// Links b and c are each other's parent, apart from the tree: every link
// has one parent, so urdfdom finds a single root, but no walk reaches them
// (found by fuzzing: they were silently left out, and leaked).
constexpr char kDetachedLoop[] = R"(<robot name="detached">
  <link name="base"/><link name="a"/><link name="b"/><link name="c"/>
  <joint name="base_a" type="fixed"><parent link="base"/><child link="a"/></joint>
  <joint name="b_c" type="fixed"><parent link="b"/><child link="c"/></joint>
  <joint name="c_b" type="fixed"><parent link="c"/><child link="b"/></joint>
</robot>
)";

TEST(RobotModel, LoopApartFromTheTreeNamesALinkAndTheRoot) {
  const std::string msg = error_of([&] { RobotModel::from_urdf_string(kDetachedLoop, ""); });
  EXPECT_TRUE(contains(msg, "link 'b' is not connected to the root link 'base'")) << msg;
}

TEST(RobotModel, MissingCameraFrameIsNamed) {
  RobotModelOptions options;
  options.camera_frame = "head_camera";
  const std::string msg = error_of([&] { RobotModel::from_urdf_string(kTree, "", options); });
  EXPECT_TRUE(contains(msg, "'head_camera'")) << msg;
}

// A gripper: finger_b mimics finger_a (multiplier -2, offset 0.01 m) and
// tip_b mimics finger_b: both follow finger_a, the only DOF.
std::string mimic_urdf(const std::string& leader_of_b, const std::string& leader_of_tip) {
  return R"(<robot name="gripper">
  <link name="hand"/><link name="a"/><link name="b"/><link name="tip"/>
  <link name="camera"/>
  <joint name="cam" type="fixed"><parent link="hand"/><child link="camera"/></joint>
  <joint name="finger_a" type="prismatic"><parent link="hand"/><child link="a"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="1" velocity="1"/></joint>
  <joint name="finger_b" type="prismatic"><parent link="hand"/><child link="b"/>
    <axis xyz="0 1 0"/><limit lower="-0.1" upper="0.1" effort="1" velocity="1"/>
    <mimic joint=")" +
         leader_of_b + R"(" multiplier="-2" offset="0.01"/></joint>
  <joint name="finger_tip" type="revolute"><parent link="b"/><child link="tip"/>
    <origin xyz="0 0 0.05"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
    <mimic joint=")" +
         leader_of_tip + R"(" multiplier="10"/></joint>
</robot>
)";
}

TEST(RobotModel, MimicJointsFollowTheirLeaderWithoutStateOfTheirOwn) {
  RobotModelOptions options;
  options.camera_frame = "camera";
  const RobotModel model =
      RobotModel::from_urdf_string(mimic_urdf("finger_a", "finger_b"), "", options);
  ASSERT_EQ(model.num_joints(), 1 + 6);  // finger_a and the virtual camera joints
  const int a = model.joint_index("finger_a");
  const std::string msg = error_of([&] { model.joint_index("finger_b"); });
  EXPECT_TRUE(contains(msg, "mimic of 'finger_a'")) << msg;
  const LinkSet moved = model.links_moved_by(a);
  for (const std::string link : {"a", "b", "tip"})
    EXPECT_TRUE(moved[model.link_index(link)]) << link;
  EXPECT_FALSE(moved[model.link_index("camera")]);

  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.num_joints());
  q[a] = 0.03;
  KinematicsState state(model);
  forward_kinematics(model, q, state);
  const double b_m = -2 * 0.03 + 0.01;  // finger_b
  EXPECT_NEAR(state.T_root_link[model.link_index("a")].translation().y(), 0.03, 1e-12);
  EXPECT_NEAR(state.T_root_link[model.link_index("b")].translation().y(), b_m, 1e-12);
  // The tip turns by 10 x finger_b's value (a chain of mimics).
  const Eigen::AngleAxisd tip(state.T_root_link[model.link_index("tip")].linear());
  EXPECT_NEAR(tip.angle() * tip.axis().x(), 10 * b_m, 1e-9);
}

TEST(RobotModel, MimicOfAMissingJointOrACycleNamesTheJointAndFile) {
  const fs::path dir = fresh_test_dir();
  RobotModelOptions options;
  options.camera_frame = "camera";
  const fs::path missing = dir / "missing.urdf";
  write_file(missing, mimic_urdf("no_such_joint", "finger_b"));
  std::string msg = error_of([&] { RobotModel::from_urdf_file(missing.string(), options); });
  EXPECT_TRUE(contains(msg, missing.string()) && contains(msg, "'finger_b'") &&
              contains(msg, "'no_such_joint'"))
      << msg;
  const fs::path cycle = dir / "cycle.urdf";
  write_file(cycle, mimic_urdf("finger_tip", "finger_b"));
  msg = error_of([&] { RobotModel::from_urdf_file(cycle.string(), options); });
  EXPECT_TRUE(contains(msg, cycle.string()) && contains(msg, "cycle")) << msg;
  const fs::path fixed = dir / "fixed.urdf";
  write_file(fixed, mimic_urdf("cam", "finger_b"));
  msg = error_of([&] { RobotModel::from_urdf_file(fixed.string(), options); });
  EXPECT_TRUE(contains(msg, fixed.string()) && contains(msg, "'cam'")) << msg;
}

// Meshes by package:// and relative paths, each visual with an origin and a
// scale; two visuals merge into one link mesh.
constexpr char kMeshes[] = R"(<robot name="m">
  <link name="base_link">
    <visual><origin xyz="1 0 0"/>
      <geometry><mesh filename="package://my_models/meshes/pkg_cube.obj" scale="2 2 2"/></geometry></visual>
    <visual><origin xyz="0 0 -1" rpy="0 0 1.5707963267948966"/>
      <geometry><mesh filename="meshes/cube.obj"/></geometry></visual>
  </link>
  <link name="camera_optical_frame"/>
  <joint name="mount" type="fixed"><parent link="base_link"/><child link="camera_optical_frame"/></joint>
</robot>
)";

TEST(RobotModel, MeshesResolveScaleAndPlaceEveryVisual) {
  const fs::path dir = fresh_test_dir();
  // The package mesh is only under <search folder>/NAME/rest.
  fs::create_directories(dir / "pkg" / "my_models" / "meshes");
  fs::create_directories(dir / "urdf" / "meshes");
  write_file(dir / "pkg" / "my_models" / "meshes" / "pkg_cube.obj", kUnitCubeObj);
  write_file(dir / "urdf" / "meshes" / "cube.obj", kUnitCubeObj);
  write_file(dir / "urdf" / "robot.urdf", kMeshes);
  RobotModelOptions options;
  options.mesh_search_paths = {(dir / "pkg").string()};
  const RobotModel model =
      RobotModel::from_urdf_file((dir / "urdf" / "robot.urdf").string(), options);
  const TriangleMesh& mesh = model.link(0).mesh;
  EXPECT_EQ(mesh.triangles.size(), 24u);
  // First cube: [0,2]^3 shifted by x + 1. Second: [0,1]^3 turned 90 degrees
  // about z ((x, y) -> (-y, x)), shifted by z - 1.
  Eigen::Vector3f lo = mesh.vertices_m[0], hi = mesh.vertices_m[0];
  for (const Eigen::Vector3f& v : mesh.vertices_m) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3f(-1, 0, -1), 1e-6f)) << lo.transpose();
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3f(3, 2, 2), 1e-6f)) << hi.transpose();
}

TEST(RobotModel, MissingMeshNamesMeshLinkAndFile) {
  const fs::path dir = fresh_test_dir();
  write_file(dir / "robot.urdf", kMeshes);
  const std::string msg =
      error_of([&] { RobotModel::from_urdf_file((dir / "robot.urdf").string()); });
  EXPECT_TRUE(contains(msg, "cube.obj") && contains(msg, "'base_link'") &&
              contains(msg, "robot.urdf"))
      << msg;
  // Present but unreadable as a mesh.
  fs::create_directories(dir / "meshes");
  write_file(dir / "meshes" / "cube.obj", "not a mesh\n");
  fs::create_directories(dir / "my_models" / "meshes");
  write_file(dir / "my_models" / "meshes" / "pkg_cube.obj", kUnitCubeObj);
  const std::string msg2 =
      error_of([&] { RobotModel::from_urdf_file((dir / "robot.urdf").string()); });
  EXPECT_TRUE(contains(msg2, "cube.obj") && contains(msg2, "'base_link'")) << msg2;
}

// The project's robot in both variants (primitives; STL/OBJ/DAE meshes found
// by relative and package:// paths) has the documented joints and frames, the
// same kinematics, and a shape on every arm link.
TEST(RobotModel, LoadsTheProjectRobots) {
  const std::string models = std::string(ARTTRACK_SOURCE_DIR) + "/models/";
  const RobotModel primitives = RobotModel::from_urdf_file(models + "dual_arm.urdf");
  const RobotModel meshes = RobotModel::from_urdf_file(models + "dual_arm_meshes.urdf");
  for (const RobotModel* model : {&primitives, &meshes}) {
    ASSERT_EQ(model->num_joints(), 2 * 7 + 2 + 6) << model->source();
    for (const std::string side : {"left", "right"}) {
      for (int i = 1; i <= 7; ++i) {
        const int j = model->joint_index(side + "_arm_joint_" + std::to_string(i));
        EXPECT_EQ(model->joint_type(j), JointType::kRevolute);
        EXPECT_LT(model->joint_lower(j), model->joint_upper(j));
        EXPECT_FALSE(model->link(model->joint_child_link(j)).mesh.empty())
            << side << " joint " << i << " moves a link without shape";
      }
      model->link_index(side + "_hand");
      model->link_index(side + "_ee");
    }
    model->joint_index("head_pan_joint");
    model->joint_index("head_tilt_joint");
    model->link_index("camera_link");
    EXPECT_EQ(model->link_name(model->nominal_camera_link()), "camera_optical_frame");
    EXPECT_TRUE(model->is_virtual_joint(model->joint_index("camera_offset_yaw")));
  }
  ASSERT_EQ(primitives.joint_names(), meshes.joint_names());
  KinematicsState a(primitives), b(meshes);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::VectorXd q(primitives.num_joints());
  for (int j = 0; j < q.size(); ++j) q[j] = U(rng);
  forward_kinematics(primitives, q, a);
  forward_kinematics(meshes, q, b);
  for (int l = 0; l < primitives.num_links(); ++l) {
    const int lm = meshes.link_index(primitives.link_name(l));
    EXPECT_TRUE(a.T_root_link[l].isApprox(b.T_root_link[lm], 1e-12)) << primitives.link_name(l);
  }
}

}  // namespace
}  // namespace arttrack

namespace arttrack {
namespace {

// A URDF of `links` links below base_link, in chains of `depth` joints.
std::string chain_urdf(int links, int depth) {
  std::string text =
      "<robot name=\"chain\"><link name=\"base_link\"/><link "
      "name=\"camera_optical_frame\"/><joint name=\"camera\" type=\"fixed\"><parent "
      "link=\"base_link\"/><child link=\"camera_optical_frame\"/></joint>\n";
  for (int i = 0; i < links; ++i) {
    const std::string name = "l" + std::to_string(i);
    const std::string parent = i % depth == 0 ? "base_link" : "l" + std::to_string(i - 1);
    text += "<link name=\"" + name + "\"/><joint name=\"j" + std::to_string(i) +
            "\" type=\"revolute\"><parent link=\"" + parent + "\"/><child link=\"" + name +
            "\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" "
            "velocity=\"1\"/></joint>\n";
  }
  return text + "</robot>\n";
}

// Bounds before cost (model_limits.h): links, joints and chain depth are
// checked right after parsing, naming the file, the count and the limit.
TEST(RobotModel, SizeLimitsAreCheckedRightAfterParsing) {
  const fs::path dir = fresh_test_dir();
  write_file(dir / "long_chain.urdf", chain_urdf(2000, 2000));
  const auto start = std::chrono::steady_clock::now();
  std::string msg =
      error_of([&] { RobotModel::from_urdf_file((dir / "long_chain.urdf").string()); });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(contains(msg, "long_chain.urdf") && contains(msg, "2002 links, more than the 1000"))
      << msg;
  EXPECT_LT(seconds, 1.0);

  write_file(dir / "deep.urdf", chain_urdf(ModelLimits::kMaxChainDepth + 1, 1000));
  msg = error_of([&] { RobotModel::from_urdf_file((dir / "deep.urdf").string()); });
  EXPECT_TRUE(contains(msg, "deep.urdf") && contains(msg, "link 'l90' is 91 joints from the root"))
      << msg;
  EXPECT_NO_THROW(RobotModel::from_urdf_string(chain_urdf(ModelLimits::kMaxChainDepth, 1000), ""));
  // Many links in shallow chains: within the limits.
  EXPECT_NO_THROW(RobotModel::from_urdf_string(chain_urdf(990, 50), ""));
}

TEST(RobotModel, MeshTrianglesAreBoundedBeforeABinaryStlIsRead) {
  const fs::path dir = fresh_test_dir();
  // A binary STL's header declares more triangles than the limit; the
  // triangles themselves are never read (the file is only as long as
  // declared: 84 + 50 n bytes, sparse here).
  const std::uint32_t n = ModelLimits::kMaxMeshTriangles + 1;
  {
    std::ofstream out(dir / "huge.stl", std::ios::binary);
    out.write(std::string(80, ' ').data(), 80);
    out.write(reinterpret_cast<const char*>(&n), 4);
  }
  fs::resize_file(dir / "huge.stl", 84 + 50 * std::uintmax_t(n));
  write_file(dir / "huge.urdf", R"(<robot name="r"><link name="camera_optical_frame">
    <visual><geometry><mesh filename="huge.stl"/></geometry></visual></link></robot>)");
  const auto start = std::chrono::steady_clock::now();
  const std::string msg =
      error_of([&] { RobotModel::from_urdf_file((dir / "huge.urdf").string()); });
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  EXPECT_TRUE(contains(msg, "huge.urdf") && contains(msg, "5000001 mesh triangles") &&
              contains(msg, "'huge.stl' of link 'camera_optical_frame'"))
      << msg;
}

// XML that urdfdom's reader would recurse into without end (it crashed at
// 200 000 nested elements) or expand (entities) is refused first.
TEST(RobotModel, DeepXmlAndEntitiesAreRefusedBeforeUrdfdom) {
  std::string nested = "<robot name=\"r\">\n<link name=\"base_link\"/>\n";
  for (int i = 0; i < 200000; ++i) nested += "<a x=\"1>2\">";
  for (int i = 0; i < 200000; ++i) nested += "</a>";
  std::string msg = error_of([&] { RobotModel::from_urdf_string(nested + "</robot>", ""); });
  EXPECT_TRUE(contains(msg, "line 3: elements nested more than 100 deep")) << msg;
  msg = error_of([&] {
    RobotModel::from_urdf_string(
        "<?xml version=\"1.0\"?>\n<!DOCTYPE r [\n<!ENTITY a \"aaaa\">\n]>\n<robot name=\"&a;\"/>",
        "");
  });
  EXPECT_TRUE(contains(msg, "line 3: an XML entity declaration")) << msg;
  // Comments, declarations, self-closing tags and '>' in values do not nest.
  std::string flat = "<?xml version=\"1.0\"?>\n<!-- <a><a><a> -->\n<robot name=\"r\">";
  for (int i = 0; i < 500; ++i) flat += "<link name=\"l" + std::to_string(i) + "\"/><!-- <x> -->";
  const std::string why = error_of([&] { RobotModel::from_urdf_string(flat + "</robot>", ""); });
  EXPECT_TRUE(!why.empty() && !contains(why, "nested")) << why;  // urdfdom's: 500 roots
}

// Text read from a file (e.g. with a camera mount added in memory) is named
// as the file in messages.
TEST(RobotModel, TextFromAFileIsNamedAsTheFile) {
  const std::string msg = error_of([&] {
    RobotModel::from_urdf_string("<robot name=\"x\"><link name=\"a\"></robot", "", {},
                                 "/data/robot.urdf");
  });
  EXPECT_TRUE(contains(msg, "URDF file '/data/robot.urdf'")) << msg;
  EXPECT_FALSE(contains(msg, "URDF string")) << msg;
}

// package://NAME/... as ROS finds it without a search path: an ancestor
// folder whose package.xml names the package (the simulator looks there too).
TEST(RobotModel, PackageFoundThroughPackageXml) {
  const fs::path dir = fresh_test_dir() / "my_robot_description";
  fs::create_directories(dir / "urdf");
  fs::create_directories(dir / "meshes");
  write_file(dir / "package.xml", "<package><name>my_robot</name></package>");
  write_file(dir / "meshes" / "pkg_cube.obj", kUnitCubeObj);
  write_file(dir / "urdf" / "robot.urdf", R"(<robot name="r"><link name="camera_optical_frame">
    <visual><geometry><mesh filename="package://my_robot/meshes/pkg_cube.obj"/></geometry>
    </visual></link></robot>)");
  const RobotModel model = RobotModel::from_urdf_file((dir / "urdf" / "robot.urdf").string());
  EXPECT_EQ(model.link(0).mesh.triangles.size(), 12u);
}

}  // namespace
}  // namespace arttrack
