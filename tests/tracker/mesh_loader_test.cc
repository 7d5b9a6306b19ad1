#include "arttrack/tracker/mesh_loader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>

#include "../expect_error.h"
#include "../mesh_checks.h"
#include "../test_files.h"
#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

namespace fs = std::filesystem;

using test_support::closed_and_consistent;
using test_support::expect_error_naming;
using test_support::fresh_test_dir;
using test_support::kUnitCubeObj;
using test_support::signed_volume_m3;
using test_support::write_file;

bool has_vertex(const TriangleMesh& mesh, const Eigen::Vector3f& p, float tol = 1e-6f) {
  for (const Eigen::Vector3f& v : mesh.vertices_m) {
    if ((v - p).norm() < tol) return true;
  }
  return false;
}

// Two geometries (a triangle and a quad), placed by nested nodes with
// translate, matrix and rotate transforms, in centimetres, Z up.
constexpr char kTwoMeshDae[] = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tri" name="tri"><mesh>
      <source id="tri_pos"><float_array id="tri_arr" count="9">0 0 0 1 0 0 0 1 0</float_array>
        <technique_common><accessor source="#tri_arr" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="tri_vtx"><input semantic="POSITION" source="#tri_pos"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#tri_vtx" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
    <geometry id="quad" name="quad"><mesh>
      <source id="quad_pos"><float_array id="quad_arr" count="12">0 0 0 2 0 0 2 2 0 0 2 0</float_array>
        <technique_common><accessor source="#quad_arr" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="quad_vtx"><input semantic="POSITION" source="#quad_pos"/></vertices>
      <polylist count="1"><input semantic="VERTEX" source="#quad_vtx" offset="0"/>
        <vcount>4</vcount><p>0 1 2 3</p></polylist>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene">
      <node id="a" name="a"><translate>10 0 0</translate><instance_geometry url="#tri"/></node>
      <node id="b" name="b"><matrix>1 0 0 0 0 1 0 0 0 0 1 5 0 0 0 1</matrix>
        <node id="c" name="c"><rotate>0 0 1 90</rotate><instance_geometry url="#quad"/></node>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";

TEST(MeshLoader, DaeLoadsEverySubMeshWithNodeTransformsAndUnits) {
  const fs::path path = fresh_test_dir() / "two.dae";
  write_file(path, kTwoMeshDae);
  const TriangleMesh mesh = load_mesh(path.string());
  EXPECT_EQ(mesh.triangles.size(), 3u);  // the triangle and the quad's two halves
  EXPECT_EQ(mesh.vertices_m.size(), 7u);
  // Triangle: translated 10 cm along x. Quad: turned 90 degrees about z,
  // lifted 5 cm. Centimetres become metres; Z stays up (no Y-up rotation).
  for (const Eigen::Vector3f& p : {Eigen::Vector3f(0.10f, 0, 0), Eigen::Vector3f(0.11f, 0, 0),
                                   Eigen::Vector3f(0.10f, 0.01f, 0)}) {
    EXPECT_TRUE(has_vertex(mesh, p)) << p.transpose();
  }
  for (const Eigen::Vector3f& p :
       {Eigen::Vector3f(0, 0, 0.05f), Eigen::Vector3f(0, 0.02f, 0.05f),
        Eigen::Vector3f(-0.02f, 0.02f, 0.05f), Eigen::Vector3f(-0.02f, 0, 0.05f)}) {
    EXPECT_TRUE(has_vertex(mesh, p)) << p.transpose();
  }
}

// A COLLADA file whose geometry does not match its own counts is refused
// before assimp reads it (assimp 5.2 grew to gigabytes on one such 5 kB
// file, tests/fuzz/regressions/mesh/collada_oom), naming the file, the
// element, its line and the problem.
TEST(MeshLoader, DaeInconsistentWithItsCountsIsRefusedNamingTheElement) {
  const fs::path dir = fresh_test_dir();
  const auto error_with = [&](const std::string& from, const std::string& to) {
    std::string text = kTwoMeshDae;
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const fs::path path = dir / "bad.dae";
    write_file(path, text);
    return test_support::error_of([&] { load_mesh(path.string()); });
  };
  EXPECT_EQ(error_with("<p>0 1 2</p>", "<p>0 1 2</p>"), "");  // the valid file
  struct Case {
    std::string from, to, message;
  };
  for (const Case& c : std::vector<Case>{
           {"<p>0 1 2</p>", "<p>0 1</p>",
            "bad.dae': line 11 <p>: 2 indices where triangles count=\"1\" with 1 per vertex needs "
            "3"},
           {"<p>0 1 2</p>", "<p>0 1 \x14</p>", "<p>: '\\x14' is not a non-negative integer"},
           {"<p>0 1 2</p>", "<p>0 1 3</p>",
            "<p>: index 3 (item 3) is past the 3 items of its input"},
           {"<vcount>4</vcount>", "<vcount>4 3</vcount>",
            "<vcount>: 2 polygons where polylist count=\"1\""},
           {"accessor source=\"#tri_arr\" count=\"3\"", "accessor source=\"#tri_arr\" count=\"4\"",
            "<accessor>: reads 4 items of 3 values from 9"},
           {"float_array id=\"tri_arr\" count=\"9\"", "float_array id=\"tri_arr\" count=\"900\"",
            "<float_array>: count=\"900\" but 9 values"},
           {"<input semantic=\"POSITION\" source=\"#tri_pos\"/>",
            "<input semantic=\"NORMAL\" source=\"#tri_pos\"/>",
            "<vertices>: no <input semantic=\"POSITION\">"},
           {"source=\"#tri_vtx\"", "source=\"#nowhere\"",
            "<input>: source '#nowhere' is not defined"},
           {"<triangles count=\"1\">", "<triangles count=\"99999999999\">",
            "99999999999 is more than the 5000000 arttrack takes here"},
           // No input to split the indices by: an error, not a division by zero.
           {"<triangles count=\"1\"><input semantic=\"VERTEX\" source=\"#tri_vtx\" offset=\"0\"/>",
            "<triangles count=\"0\">", "line 11 <triangles>: no <input>"}})
    EXPECT_NE(error_with(c.from, c.to).find(c.message), std::string::npos) << c.to;
}

// Binary STL whose 80-byte header starts with "solid", as many CAD tools write.
void write_binary_stl(const fs::path& path, const std::vector<std::array<float, 9>>& triangles) {
  std::ofstream out(path, std::ios::binary);
  char header[80];
  std::memset(header, ' ', sizeof header);
  std::memcpy(header, "solid part exported by CAD", 26);
  out.write(header, sizeof header);
  const uint32_t n = uint32_t(triangles.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 0};
    out.write(reinterpret_cast<const char*>(normal), sizeof normal);
    out.write(reinterpret_cast<const char*>(t.data()), 9 * sizeof(float));
    const uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
}

TEST(MeshLoader, BinaryStlWithSolidHeaderAndScale) {
  const fs::path path = fresh_test_dir() / "square.stl";
  write_binary_stl(path, {{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 0}});
  const TriangleMesh mesh = load_mesh(path.string(), Eigen::Vector3d(2, 3, 4));
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.vertices_m.size(), 4u);  // the shared corners welded
  for (const Eigen::Vector3f& p : {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(2, 0, 0),
                                   Eigen::Vector3f(2, 3, 0), Eigen::Vector3f(0, 3, 0)}) {
    EXPECT_TRUE(has_vertex(mesh, p)) << p.transpose();
  }
}

TEST(MeshLoader, ObjQuadsAreTriangulatedClosedAndOutward) {
  const fs::path path = fresh_test_dir() / "cube.obj";
  write_file(path, kUnitCubeObj);
  const TriangleMesh mesh = load_mesh(path.string());
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_EQ(mesh.vertices_m.size(), 8u);
  EXPECT_TRUE(closed_and_consistent(mesh));
  EXPECT_NEAR(signed_volume_m3(mesh), 1.0, 1e-6);
}

TEST(MeshLoader, MissingAndGarbageFilesNameTheFile) {
  const fs::path dir = fresh_test_dir();
  expect_error_naming([&] { load_mesh((dir / "nowhere.stl").string()); }, "nowhere.stl");
  write_file(dir / "garbage.obj", "this is not a mesh\n");
  expect_error_naming([&] { load_mesh((dir / "garbage.obj").string()); }, "garbage.obj");
}

TEST(MeshLoader, PrimitivesAreClosedOutwardWithTheRightVolume) {
  const double pi = std::numbers::pi;
  const TriangleMesh box = make_box(Eigen::Vector3d(0.2, 0.3, 0.4));
  EXPECT_TRUE(closed_and_consistent(box));
  EXPECT_NEAR(signed_volume_m3(box), 0.2 * 0.3 * 0.4, 1e-8);

  // The area-preserving polygon makes the cylinder's volume exact.
  const TriangleMesh cylinder = make_cylinder(0.05, 0.3, 32);
  EXPECT_TRUE(closed_and_consistent(cylinder));
  EXPECT_NEAR(signed_volume_m3(cylinder), pi * 0.05 * 0.05 * 0.3, 1e-7);
  EXPECT_EQ(cylinder.triangles.size(), 4u * 32);

  // The sphere is scaled to hold the sphere's volume, at any tessellation.
  for (int segments : {6, 12, 16, 48}) {
    const TriangleMesh sphere = make_sphere(0.1, segments);
    EXPECT_TRUE(closed_and_consistent(sphere));
    EXPECT_NEAR(signed_volume_m3(sphere), 4.0 / 3 * pi * 1e-3, 1e-6 * 4.0 / 3 * pi * 1e-3)
        << segments;
  }
}

TEST(MeshLoader, AppendWithMirrorKeepsTrianglesOutward) {
  TriangleMesh mirrored;
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  T.linear() = Eigen::Vector3d(-1, 1, 1).asDiagonal();
  T.translation() = Eigen::Vector3d(1, 2, 3);
  mirrored.append(make_box(Eigen::Vector3d(0.1, 0.2, 0.3)), T);
  EXPECT_TRUE(closed_and_consistent(mirrored));
  EXPECT_NEAR(signed_volume_m3(mirrored), 0.1 * 0.2 * 0.3, 1e-7);
}

// Two boxes side by side, one inside out, the other with one face flipped
// (as published meshes come): both closed parts are wound outward again.
TEST(MeshLoader, OrientPartsTurnsClosedPartsOutward) {
  TriangleMesh mesh;
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  mesh.append(make_box(Eigen::Vector3d(0.1, 0.2, 0.3)), T);
  T.translation() = Eigen::Vector3d(0.5, 0, 0);
  mesh.append(make_box(Eigen::Vector3d(0.3, 0.1, 0.2)), T);
  for (int t = 0; t < 12; ++t)
    std::swap(mesh.triangles[std::size_t(t)][1], mesh.triangles[std::size_t(t)][2]);
  std::swap(mesh.triangles[17][0], mesh.triangles[17][1]);
  ASSERT_FALSE(closed_and_consistent(mesh));

  const MeshOrientation report = orient_parts(mesh);
  EXPECT_EQ(report.parts, 2);
  EXPECT_EQ(report.turned_parts, 2);
  EXPECT_EQ(report.open_parts, 0);
  EXPECT_TRUE(closed_and_consistent(mesh));
  EXPECT_NEAR(signed_volume_m3(mesh), 2 * 0.1 * 0.2 * 0.3, 1e-7);

  // Already outward: nothing to do.
  const TriangleMesh before = mesh;
  const MeshOrientation again = orient_parts(mesh);
  EXPECT_EQ(again.turned_parts, 0);
  EXPECT_EQ(mesh.triangles, before.triangles);
}

// A box without its top (a border) wound inside out, three triangles on one
// edge (not a surface) and a triangle's two faces back to back (closed, no
// volume): the box, open but enclosing a volume, is turned outward; the
// others have no outside and are left as they are.
TEST(MeshLoader, OrientPartsTurnsOpenPartsOnlyWhenTheyEncloseAVolume) {
  TriangleMesh open_box = make_box(Eigen::Vector3d(0.2, 0.2, 0.2));
  std::erase_if(open_box.triangles, [&](const Eigen::Vector3i& t) {
    return open_box.vertices_m[t[0]].z() > 0 && open_box.vertices_m[t[1]].z() > 0 &&
           open_box.vertices_m[t[2]].z() > 0;
  });
  ASSERT_EQ(open_box.triangles.size(), 10u);
  TriangleMesh fin;
  fin.vertices_m = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.triangles = {{0, 1, 2}, {0, 1, 3}, {1, 0, 4}};
  TriangleMesh sheet;
  sheet.vertices_m = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 1}};

  TriangleMesh mesh = open_box;
  for (Eigen::Vector3i& t : mesh.triangles) std::swap(t[1], t[2]);  // inside out
  mesh.append(fin, Eigen::Affine3d(Eigen::Translation3d(1, 0, 0)));
  mesh.append(sheet, Eigen::Affine3d(Eigen::Translation3d(3, 0, 0)));
  const TriangleMesh before = mesh;
  const MeshOrientation report = orient_parts(mesh);
  // The fin's triangles share only the edge of three: a part each.
  EXPECT_EQ(report.parts, 1 + 3 + 1);
  EXPECT_EQ(report.open_parts, 1 + 3);
  EXPECT_EQ(report.open_triangles, 13);
  // The open box still encloses a volume: turned outward like a closed one.
  EXPECT_EQ(report.turned_parts, 1);
  for (std::size_t t = 0; t < open_box.triangles.size(); ++t)
    EXPECT_EQ(mesh.triangles[t], open_box.triangles[t]);
  for (std::size_t t = open_box.triangles.size(); t < mesh.triangles.size(); ++t)
    EXPECT_EQ(mesh.triangles[t], before.triangles[t]);
}

}  // namespace
}  // namespace arttrack
