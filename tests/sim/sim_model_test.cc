// The model builder: meshes of every format MuJoCo 2.2 cannot read arrive
// with the right geometry (checked on MuJoCo's compiled vertices), body
// frames are the URDF's at full precision, the scene is assembled as
// documented, and bad input is an InputError naming the item.
#include "arttrack/sim/sim_model.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../error_of.h"
#include "../scratch_dir.h"
#include "arttrack/sim/simulator.h"
#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;

fs::path model_scratch_dir() { return test_support::program_scratch_dir().path(); }

using test_support::write_scratch_file;

// Corners of an axis-aligned box [0, sx] x [0, sy] x [0, sz]: index x + 2y + 4z.
std::vector<Eigen::Vector3d> box_corners(const Eigen::Vector3d& s) {
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back(i & 1 ? s.x() : 0, i & 2 ? s.y() : 0, i & 4 ? s.z() : 0);
  return v;
}
// Outward counter-clockwise triangles of that box.
constexpr int kBoxFaces[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                  {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};

std::string ascii_stl_box(const Eigen::Vector3d& s) {
  const auto v = box_corners(s);
  std::ostringstream out;
  out << "solid box\n";
  for (const auto& f : kBoxFaces) {
    out << " facet normal 0 0 0\n  outer loop\n";
    for (int k : f) out << "   vertex " << v[k].x() << " " << v[k].y() << " " << v[k].z() << "\n";
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid box\n";
  return out.str();
}

// A binary STL whose 80-byte header begins with "solid", the pitfall that
// makes text-sniffing readers take it for ASCII.
std::string binary_stl_box_solid_header(const Eigen::Vector3d& s) {
  const auto v = box_corners(s);
  std::string out(84 + 50 * 12, '\0');
  std::memcpy(out.data(), "solid exported by a CAD tool", 28);
  const uint32_t n = 12;
  std::memcpy(out.data() + 80, &n, 4);
  for (int i = 0; i < 12; ++i)
    for (int k = 0; k < 3; ++k) {
      const float xyz[3] = {float(v[kBoxFaces[i][k]].x()), float(v[kBoxFaces[i][k]].y()),
                            float(v[kBoxFaces[i][k]].z())};
      std::memcpy(out.data() + 84 + 50 * i + 12 + 12 * k, xyz, 12);
    }
  return out;
}

// COLLADA in centimetres, Z_UP, with a node translation: the box 10 x 20 x
// 30 cm moved 5 cm along x. Expected in metres: [0.05, 0.15] x [0, 0.2] x [0, 0.3].
std::string collada_box() {
  const auto v = box_corners({10, 20, 30});
  std::ostringstream pos, idx;
  for (const auto& p : v) pos << p.x() << " " << p.y() << " " << p.z() << " ";
  for (const auto& f : kBoxFaces) idx << f[0] << " " << f[1] << " " << f[2] << " ";
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="box-mesh" name="box"><mesh>
      <source id="box-pos">
        <float_array id="box-pos-array" count="24">)" +
         pos.str() + R"(</float_array>
        <technique_common><accessor source="#box-pos-array" count="8" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="box-vtx"><input semantic="POSITION" source="#box-pos"/></vertices>
      <triangles count="12"><input semantic="VERTEX" source="#box-vtx" offset="0"/><p>)" +
         idx.str() + R"(</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="Scene"><node id="n" name="n"><translate>5 0 0</translate>
      <instance_geometry url="#box-mesh"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";
}

// A hexagonal prism (circumradius 0.1, height 0.2) as an OBJ with hexagon
// faces and two objects: MuJoCo 2.2 would reject the hexagons and keep only
// the first object.
std::string obj_hex_prism() {
  std::ostringstream out;
  for (int z = 0; z < 2; ++z)
    for (int i = 0; i < 6; ++i)
      out << "v " << 0.1 * std::cos(i * M_PI / 3) << " " << 0.1 * std::sin(i * M_PI / 3) << " "
          << 0.2 * z << "\n";
  out << "o caps\nf 6 5 4 3 2 1\nf 7 8 9 10 11 12\no sides\n";
  for (int i = 0; i < 6; ++i) {
    const int a = i + 1, b = (i + 1) % 6 + 1;
    out << "f " << a << " " << b << " " << b + 6 << " " << a + 6 << "\n";
  }
  return out.str();
}

// World-frame bounding box of one compiled geom's mesh vertices.
Eigen::AlignedBox3d geom_world_box(const mjModel* m, const mjData* d, int geom) {
  Eigen::AlignedBox3d box;
  const int mesh = m->geom_dataid[geom];
  const Eigen::Map<const Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>> R(d->geom_xmat + 9 * geom);
  const Eigen::Map<const Eigen::Vector3d> p(d->geom_xpos + 3 * geom);
  for (int i = 0; i < m->mesh_vertnum[mesh]; ++i) {
    const float* v = m->mesh_vert + 3 * (m->mesh_vertadr[mesh] + i);
    box.extend(R * Eigen::Vector3d(v[0], v[1], v[2]) + p);
  }
  return box;
}

// The visual (group 1) mesh geom of a body.
int visual_geom(const mjModel* m, const std::string& body) {
  const int b = mj_name2id(m, mjOBJ_BODY, body.c_str());
  for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g)
    if (m->geom_group[g] == kGroupRobotVisual) return g;
  return -1;
}

std::string mesh_link(const std::string& name, double x, const std::string& file,
                      const std::string& scale = "") {
  const std::string s = scale.empty() ? "" : " scale=\"" + scale + "\"";
  return "<link name=\"" + name + "\"><visual><geometry><mesh filename=\"" + file + "\"" + s +
         "/></geometry></visual></link><joint name=\"" + name +
         "_joint\" type=\"fixed\"><parent link=\"base_link\"/><child link=\"" + name +
         "\"/><origin xyz=\"" + std::to_string(x) + " 0 0\"/></joint>";
}

SceneDescription robot_scene(const fs::path& urdf) {
  SceneDescription s;
  s.urdf_path = urdf;
  s.camera_link = "base_link";
  s.end_effector_links = {};
  s.width = 64;
  s.height = 48;
  return s;
}

void expect_box(const Eigen::AlignedBox3d& got, const Eigen::Vector3d& lo,
                const Eigen::Vector3d& hi, const std::string& what) {
  EXPECT_LT((got.min() - lo).cwiseAbs().maxCoeff(), 1e-6)
      << what << " min " << got.min().transpose();
  EXPECT_LT((got.max() - hi).cwiseAbs().maxCoeff(), 1e-6)
      << what << " max " << got.max().transpose();
}

TEST(SimModel, ConvertsEveryMeshFormatWithScaleAndUniqueNames) {
  write_scratch_file("meshes/box.dae", collada_box());
  write_scratch_file("meshes/hex.obj", obj_hex_prism());
  write_scratch_file("meshes/ascii.stl", ascii_stl_box({0.1, 0.2, 0.3}));
  write_scratch_file("meshes/a/part.stl", binary_stl_box_solid_header({0.1, 0.1, 0.1}));
  write_scratch_file("meshes/b/part.stl", binary_stl_box_solid_header({0.3, 0.2, 0.1}));
  write_scratch_file("my_pkg/box.stl", ascii_stl_box({0.1, 0.1, 0.1}));     // found by folder name
  write_scratch_file("elsewhere/box.stl", ascii_stl_box({0.2, 0.1, 0.1}));  // given in the scene
  const fs::path urdf = write_scratch_file(
      "meshes.urdf",
      "<robot name=\"m\"><link name=\"base_link\"/>" + mesh_link("dae", 1, "meshes/box.dae") +
          mesh_link("dae_scaled", 2, "meshes/box.dae", "2 2 2") +
          mesh_link("obj", 3, "meshes/hex.obj") + mesh_link("ascii", 4, "meshes/ascii.stl") +
          mesh_link("part_a", 5, "meshes/a/part.stl") +
          mesh_link("part_b", 6, "meshes/b/part.stl") +
          mesh_link("mirrored", 7, "meshes/ascii.stl", "-1 1 1") +
          mesh_link("pkg", 8, "package://my_pkg/box.stl") +
          mesh_link("pkg2", 9, "package://other_pkg/box.stl") + "</robot>");
  SceneDescription scene = robot_scene(urdf);
  scene.package_paths["other_pkg"] = model_scratch_dir() / "elsewhere";
  const auto model = build_sim_model(scene);
  Simulator sim(model);
  const mjModel* m = model->mj.get();
  const mjData* d = sim.data();
  const auto box = [&](const std::string& link) {
    const int g = visual_geom(m, link);
    EXPECT_GE(g, 0) << link;
    return g < 0 ? Eigen::AlignedBox3d() : geom_world_box(m, d, g);
  };
  const Eigen::Vector3d x(1, 0, 0);
  expect_box(box("dae"), x + Eigen::Vector3d(0.05, 0, 0), x + Eigen::Vector3d(0.15, 0.2, 0.3),
             "dae");
  expect_box(box("dae_scaled"), 2 * x + Eigen::Vector3d(0.1, 0, 0),
             2 * x + Eigen::Vector3d(0.3, 0.4, 0.6), "dae scaled");
  const double r = 0.1, ry = 0.1 * std::sin(M_PI / 3);
  expect_box(box("obj"), 3 * x + Eigen::Vector3d(-r, -ry, 0), 3 * x + Eigen::Vector3d(r, ry, 0.2),
             "obj");
  expect_box(box("ascii"), 4 * x, 4 * x + Eigen::Vector3d(0.1, 0.2, 0.3), "ascii stl");
  expect_box(box("part_a"), 5 * x, 5 * x + Eigen::Vector3d(0.1, 0.1, 0.1), "a/part.stl");
  expect_box(box("part_b"), 6 * x, 6 * x + Eigen::Vector3d(0.3, 0.2, 0.1), "b/part.stl");
  expect_box(box("mirrored"), 7 * x + Eigen::Vector3d(-0.1, 0, 0),
             7 * x + Eigen::Vector3d(0, 0.2, 0.3), "mirrored");
  expect_box(box("pkg"), 8 * x, 8 * x + Eigen::Vector3d(0.1, 0.1, 0.1), "package:// by folder");
  expect_box(box("pkg2"), 9 * x, 9 * x + Eigen::Vector3d(0.2, 0.1, 0.1), "package:// from scene");
  // The hexagonal prism keeps all its faces: 2 hexagons (4 triangles each)
  // and 6 quads (2 each).
  EXPECT_EQ(m->mesh_facenum[m->geom_dataid[visual_geom(m, "obj")]], 20);
  // A mirrored mesh keeps its outward winding: every face normal points away
  // from the mesh centre (MuJoCo centres mesh vertices on their centroid).
  const int g = visual_geom(m, "mirrored");
  const int mesh = m->geom_dataid[g];
  for (int f = 0; f < m->mesh_facenum[mesh]; ++f) {
    const int* tri = m->mesh_face + 3 * (m->mesh_faceadr[mesh] + f);
    Eigen::Vector3f v[3];
    for (int k = 0; k < 3; ++k) {
      const float* p = m->mesh_vert + 3 * (m->mesh_vertadr[mesh] + tri[k]);
      v[k] = Eigen::Vector3f(p[0], p[1], p[2]);
    }
    const Eigen::Vector3f n = (v[1] - v[0]).cross(v[2] - v[0]);
    EXPECT_GT(n.dot((v[0] + v[1] + v[2]) / 3), 0) << "face " << f;
  }
}

constexpr char kTiltedShoulderUrdf[] = R"(<robot name="arm">
  <link name="base_link"/>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/><child link="upper"/>
    <origin xyz="0.1234567890123 -0.2 0.5" rpy="0.1234567890123 0.3 -0.7"/>
    <axis xyz="0 0.6 0.8"/><limit lower="-2" upper="2" effort="50" velocity="1"/>
  </joint>
  <link name="upper">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.03" length="0.3"/></geometry></visual>
    <collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.03" length="0.3"/></geometry></collision>
  </link>
  <joint name="tool" type="fixed">
    <parent link="upper"/><child link="camera_optical_frame"/>
    <origin xyz="0 0 0.3333333333333" rpy="0 1.1 0"/>
  </joint>
  <link name="camera_optical_frame"/>
</robot>)";

TEST(SimModel, BodyFramesAreUrdfFramesAtFullPrecision) {
  const auto model =
      build_sim_model(robot_scene(write_scratch_file("arm.urdf", kTiltedShoulderUrdf)));
  const mjModel* m = model->mj.get();
  const int upper = mj_name2id(m, mjOBJ_BODY, "upper");
  EXPECT_EQ(m->body_pos[3 * upper], 0.1234567890123);
  const Eigen::Quaterniond q = Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(0.1234567890123, Eigen::Vector3d::UnitX());
  EXPECT_NEAR(
      std::abs(q.dot(Eigen::Quaterniond(m->body_quat[4 * upper], m->body_quat[4 * upper + 1],
                                        m->body_quat[4 * upper + 2], m->body_quat[4 * upper + 3]))),
      1.0, 1e-15);
  const int j = mj_name2id(m, mjOBJ_JOINT, "shoulder");
  EXPECT_NEAR(m->jnt_axis[3 * j + 1], 0.6, 1e-15);
  const int cam = mj_name2id(m, mjOBJ_BODY, "camera_optical_frame");
  EXPECT_EQ(m->body_pos[3 * cam + 2], 0.3333333333333);
}

TEST(SimModel, SceneAssembly) {
  SceneDescription s = robot_scene(write_scratch_file("arm2.urdf", kTiltedShoulderUrdf));
  s.camera_link = "camera_optical_frame";
  s.shapes.push_back({});
  s.shapes.back().name = "crate";
  s.shapes.back().size_m << 0.2, 0.2, 0.2;
  OccluderSpec person;
  person.name = "visitor";
  person.type = OccluderSpec::Type::kPerson;
  person.size_m << 1.8, 0, 0;
  s.occluders.push_back(person);
  s.joint_gains["shoulder"] = {123, 4.5};
  s.extent_m = 3.5;
  s.near_m = 0.07;
  const auto model = build_sim_model(s);
  const mjModel* m = model->mj.get();
  EXPECT_DOUBLE_EQ(m->stat.extent, 3.5);
  EXPECT_NEAR(m->vis.map.znear * m->stat.extent, 0.07, 1e-8);  // znear is a float
  EXPECT_EQ(m->vis.quality.offsamples, 0);
  ASSERT_EQ(model->joint_names, std::vector<std::string>{"shoulder"});
  const int a = model->joint_actuator[0];
  EXPECT_EQ(m->actuator_gainprm[a * mjNGAIN], 123);
  EXPECT_EQ(m->actuator_biasprm[a * mjNBIAS + 1], -123);
  EXPECT_EQ(m->actuator_biasprm[a * mjNBIAS + 2], -4.5);
  EXPECT_EQ(m->actuator_forcerange[2 * a + 1], 50);  // URDF effort
  EXPECT_EQ(model->occluder_names, std::vector<std::string>{"visitor"});
  EXPECT_GE(model->occluder_mocap[0], 0);
  // Robot geoms touch the scene, never each other; occluders touch nothing.
  for (int g = 0; g < m->ngeom; ++g) {
    const int group = m->geom_group[g];
    if (group == kGroupRobotCollision) {
      EXPECT_EQ(m->geom_contype[g] & m->geom_conaffinity[g], 0);
    } else if (group == kGroupOccluder || group == kGroupRobotVisual) {
      EXPECT_EQ(m->geom_contype[g] | m->geom_conaffinity[g], 0);
    } else {
      EXPECT_EQ(group, kGroupScene);
    }
  }
}

// Builds a scene and returns the InputError's message ("" if none).
std::string build_error(const SceneDescription& s) {
  return test_support::error_of([&] { build_sim_model(s); });
}

TEST(SimModel, BadInputNamesTheItem) {
  const fs::path arm = write_scratch_file("arm3.urdf", kTiltedShoulderUrdf);
  SceneDescription s = robot_scene(model_scratch_dir() / "no_such_robot.urdf");
  EXPECT_NE(build_error(s).find("no_such_robot.urdf"), std::string::npos) << build_error(s);

  s = robot_scene(arm);
  s.camera_link = "eye";
  EXPECT_NE(build_error(s).find("camera link 'eye'"), std::string::npos) << build_error(s);

  s = robot_scene(arm);
  s.end_effector_links = {"gripper"};
  EXPECT_NE(build_error(s).find("'gripper'"), std::string::npos) << build_error(s);

  s = robot_scene(arm);
  s.initial_joints_rad["elbow"] = 1;
  EXPECT_NE(build_error(s).find("'elbow'"), std::string::npos) << build_error(s);

  s = robot_scene(write_scratch_file("missing_mesh.urdf",
                                     "<robot name=\"r\"><link name=\"base_link\"/>" +
                                         mesh_link("hand", 0, "meshes/hand.dae") + "</robot>"));
  std::string e = build_error(s);
  EXPECT_NE(e.find("hand.dae"), std::string::npos) << e;
  EXPECT_NE(e.find("missing_mesh.urdf"), std::string::npos) << e;

  s = robot_scene(write_scratch_file(
      "bad_package.urdf", "<robot name=\"r\"><link name=\"base_link\"/>" +
                              mesh_link("hand", 0, "package://nope/x.stl") + "</robot>"));
  e = build_error(s);
  EXPECT_NE(e.find("package://nope/x.stl"), std::string::npos) << e;

  // A kinematic loop: 'upper' is the child of two joints.
  s = robot_scene(write_scratch_file("loop.urdf", R"(<robot name="r"><link name="base_link"/>
    <link name="upper"/><link name="fore"/>
    <joint name="shoulder" type="fixed"><parent link="base_link"/><child link="upper"/></joint>
    <joint name="elbow" type="fixed"><parent link="upper"/><child link="fore"/></joint>
    <joint name="wrist" type="fixed"><parent link="fore"/><child link="upper"/></joint>
    </robot>)"));
  e = build_error(s);
  EXPECT_NE(e.find("loop.urdf"), std::string::npos) << e;
  EXPECT_NE(e.find("link 'upper' is the child of joints 'shoulder' and 'wrist'"), std::string::npos)
      << e;

  // A loop apart from the tree: every link has one parent, one root.
  s = robot_scene(write_scratch_file("detached.urdf", R"(<robot name="r"><link name="base_link"/>
    <link name="b"/><link name="c"/>
    <joint name="b_c" type="fixed"><parent link="b"/><child link="c"/></joint>
    <joint name="c_b" type="fixed"><parent link="c"/><child link="b"/></joint>
    </robot>)"));
  e = build_error(s);
  EXPECT_NE(e.find("detached.urdf: link 'b' is not connected to the root link 'base_link'"),
            std::string::npos)
      << e;

  s = robot_scene(
      write_scratch_file("malformed.urdf", "<robot name=\"r\"><link name=\"base_link\">"));
  e = build_error(s);
  EXPECT_NE(e.find("malformed.urdf"), std::string::npos) << e;
}

// A moving link without <inertial> nor geometry gets the documented
// fallback mass instead of MuJoCo's "mass and inertia of moving bodies"
// error.
TEST(SimModel, MovingLinkWithoutInertialOrGeometryGetsTheFallbackMass) {
  const auto model = build_sim_model(
      robot_scene(write_scratch_file("massless.urdf", R"(<robot name="r"><link name="base_link"/>
    <joint name="j" type="revolute"><parent link="base_link"/><child link="l"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <link name="l"/></robot>)")));
  EXPECT_DOUBLE_EQ(model->mj->body_mass[model->link_body[model->link_index("l")]], 0.01);
}

}  // namespace
}  // namespace arttrack::sim

namespace arttrack::sim {
namespace {

// The second robot: no <inertial> anywhere (masses from the geometry), a
// camera the scene mounts in the world, a mimic finger. It simulates; the
// camera is where the scene puts it; the mimic finger follows its leader.
TEST(SimModel, Arm7WithoutInertialsWithAWorldCameraAndAMimicFinger) {
  const SceneDescription scene =
      load_scene(fs::path(ARTTRACK_SOURCE_DIR) / "models/arm7_scene.yaml");
  ASSERT_TRUE(scene.camera_mount.has_value());
  const auto model = build_sim_model(scene);
  const mjModel* m = model->mj.get();
  for (const std::string link : {"arm7_link1", "arm7_link4", "arm7_finger2"}) {
    const int b = model->link_body[model->link_index(link)];
    EXPECT_GT(m->body_mass[b], 0.01) << link;  // more than the fallback: from the geometry
  }
  // arm7_link4: a box 0.10 x 0.09 x 0.10 and a cylinder r 0.05 l 0.16, solid at 1000 kg/m^3.
  const int link4 = model->link_body[model->link_index("arm7_link4")];
  // (MuJoCo's saved MJCF keeps 6 digits.)
  EXPECT_NEAR(m->body_mass[link4], 1000 * (0.1 * 0.09 * 0.1 + M_PI * 0.05 * 0.05 * 0.16), 1e-5);
  EXPECT_EQ(model->joint_index("arm7_finger_joint2"), -1);  // a mimic: no servo

  Simulator sim(model);
  sim.run_until(0.5);
  const GroundTruth g = sim.ground_truth();
  const Eigen::Isometry3d& mount = scene.camera_mount->T_parent_camera;
  EXPECT_LT((g.T_world_camera.translation() - mount.translation()).norm(), 1e-9);
  EXPECT_LT((g.T_world_camera.linear() - mount.linear()).norm(), 1e-9);
  const int f1 = model->joint_id[model->joint_index("arm7_finger_joint1")];
  const int f2 = mj_name2id(m, mjOBJ_JOINT, "arm7_finger_joint2");
  ASSERT_GE(f2, 0);
  EXPECT_NEAR(sim.data()->qpos[m->jnt_qposadr[f2]], sim.data()->qpos[m->jnt_qposadr[f1]], 1e-3);
  EXPECT_NEAR(sim.data()->qpos[m->jnt_qposadr[f1]], 0.02, 2e-3);
}

TEST(SimModel, CameraMountAndMimicErrorsNameTheItem) {
  SceneDescription s = load_scene(fs::path(ARTTRACK_SOURCE_DIR) / "models/arm7_scene.yaml");
  s.camera_mount->parent_link = "arm7_link9";
  std::string e = build_error(s);
  EXPECT_NE(e.find("'arm7_link9'"), std::string::npos) << e;
  EXPECT_NE(e.find("arm7.urdf"), std::string::npos) << e;

  s.camera_mount->parent_link = "arm7_hand";  // on a link: eye-in-hand, loads
  EXPECT_EQ(build_error(s), "");
  s.camera_link = "arm7_ee";  // taken
  e = build_error(s);
  EXPECT_NE(e.find("already has a link 'arm7_ee'"), std::string::npos) << e;

  s = robot_scene(
      write_scratch_file("mimic_missing.urdf", R"(<robot name="r"><link name="base_link"/>
    <link name="a"/>
    <joint name="follower" type="revolute"><parent link="base_link"/><child link="a"/>
      <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
      <mimic joint="ghost"/></joint></robot>)"));
  e = build_error(s);
  EXPECT_NE(e.find("'follower'"), std::string::npos) << e;
  EXPECT_NE(e.find("'ghost'"), std::string::npos) << e;
  EXPECT_NE(e.find("mimic_missing.urdf"), std::string::npos) << e;
}

}  // namespace
}  // namespace arttrack::sim

namespace arttrack::sim {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A joint MuJoCo 2.2 would take but the tracker cannot (floating, planar) is
// refused before MuJoCo, naming the user's file and the joint's line there.
TEST(SimModel, FloatingJointIsRefusedAtItsLineInTheUsersFile) {
  const fs::path urdf = write_scratch_file("floating.urdf", R"(<robot name="r">
  <link name="base_link"/>
  <link name="l"/>
  <joint name="free" type="floating"><parent link="base_link"/><child link="l"/></joint>
</robot>)");
  const std::string e = build_error(robot_scene(urdf));
  EXPECT_NE(e.find(urdf.string() + ":4: joint 'free' is floating"), std::string::npos) << e;
}

// base_link and a chain of `links` links on fixed joints below it.
std::string fixed_chain_urdf(int links) {
  std::string text = "<robot name=\"chain\"><link name=\"base_link\"/>\n";
  for (int i = 0; i < links; ++i)
    text += "<link name=\"l" + std::to_string(i) + "\"/><joint name=\"j" + std::to_string(i) +
            "\" type=\"fixed\"><parent link=\"" + (i ? "l" + std::to_string(i - 1) : "base_link") +
            "\"/><child link=\"l" + std::to_string(i) + "\"/></joint>\n";
  return text + "</robot>\n";
}

// Bounds before cost (model_limits.h): a 2000-link chain was a minute in
// MuJoCo's compiler, then an error naming a temporary file.
TEST(SimModel, SizeLimitsAreCheckedBeforeMuJoCo) {
  const fs::path long_chain = write_scratch_file("long_chain.urdf", fixed_chain_urdf(2000));
  auto start = std::chrono::steady_clock::now();
  std::string e = build_error(robot_scene(long_chain));
  EXPECT_LT(seconds_since(start), 1.0);
  EXPECT_NE(e.find(long_chain.string() + ": 2001 links, more than the 1000"), std::string::npos)
      << e;

  // 100 links in one chain: within the count, past the depth.
  const fs::path deep_chain = write_scratch_file("deep_chain.urdf", fixed_chain_urdf(100));
  start = std::chrono::steady_clock::now();
  e = build_error(robot_scene(deep_chain));
  EXPECT_LT(seconds_since(start), 1.0);
  EXPECT_NE(e.find(deep_chain.string() + ": link 'l99' is 100 joints from the root, more than the "
                                         "90"),
            std::string::npos)
      << e;
  EXPECT_EQ(e.rfind(deep_chain.string(), 0), 0u) << e;  // the user's file, no temporary copy
}

// A binary STL of 4 triangles repeated `copies` times (a tetrahedron 10 cm
// across, `copies` layers on top of each other).
std::string binary_stl_tetrahedra(std::uint32_t copies) {
  const float v[4][3] = {{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {0, 0, 0.1f}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const std::uint32_t n = 4 * copies;
  std::string out(84 + 50 * std::size_t(n), '\0');
  std::memcpy(out.data() + 80, &n, 4);
  for (std::uint32_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k)
      std::memcpy(out.data() + 84 + 50 * t + 12 + 12 * k, v[faces[t % 4][k]], 12);
  return out;
}

// A mesh over MuJoCo 2.2's 200 000 triangles per STL file reaches it in
// parts (one geom each); the tracker reads it whole. (Two massless visual
// geoms on a welded link: the documented fallback mass.)
TEST(SimModel, MeshOverMuJoCosLimitPerFileArrivesInParts) {
  write_scratch_file("big.stl", binary_stl_tetrahedra(62500));  // 250 000 triangles
  const auto model = build_sim_model(robot_scene(
      write_scratch_file("big_mesh.urdf", "<robot name=\"m\"><link name=\"base_link\"/>" +
                                              mesh_link("big", 0, "big.stl") + "</robot>")));
  const mjModel* m = model->mj.get();
  const int b = mj_name2id(m, mjOBJ_BODY, "big");
  int faces = 0;
  for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
    ASSERT_EQ(m->geom_type[g], mjGEOM_MESH);
    faces += m->mesh_facenum[m->geom_dataid[g]];
  }
  EXPECT_EQ(m->body_geomnum[b], 2);
  EXPECT_EQ(faces, 250000);
}

// Collision shapes without volume (a zero radius, a flat mesh) collide with
// nothing in ROS; MuJoCo refuses them: left out, with a notice.
TEST(SimModel, CollisionShapesWithoutVolumeAreLeftOut) {
  write_scratch_file("plate.obj", "v 0 0 0\nv 0.1 0 0\nv 0.1 0.1 0\nv 0 0.1 0\nf 1 2 3\nf 1 3 4\n");
  const auto model =
      build_sim_model(robot_scene(write_scratch_file("no_volume.urdf", R"(<robot name="r">
  <link name="base_link">
    <collision><geometry><sphere radius="0"/></geometry></collision>
    <collision><geometry><mesh filename="plate.obj"/></geometry></collision>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
    <visual><geometry><mesh filename="plate.obj"/></geometry></visual>
  </link></robot>)")));
  const mjModel* m = model->mj.get();
  const int b = model->link_body[model->link_index("base_link")];
  ASSERT_EQ(m->body_geomnum[b], 2);  // the box and the visual plate
  EXPECT_EQ(m->geom_type[m->body_geomadr[b]], mjGEOM_BOX);
}

}  // namespace
}  // namespace arttrack::sim
