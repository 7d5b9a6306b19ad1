// The URDF prepared for MuJoCo 2.2 (sim/simulation/src/urdf_prepare.h, internal to
// arttrack_sim_simulation): normalised to what urdfdom reads of it, and MuJoCo's own
// errors about the prepared copy retold at the line of the user's file.
#include "urdf_prepare.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "../scratch_dir.h"

namespace arttrack::sim {
namespace {

using tinyxml2::XMLElement;

std::string text_of(const XMLElement* e) {
  tinyxml2::XMLPrinter printer(nullptr, true);
  e->Accept(&printer);
  return printer.CStr();
}

// urdfdom reads the first of a repeated element where it reads one, the
// first shape of a <geometry>, links, joints and materials only, and no
// position limits on a continuous joint.
TEST(UrdfPrepare, NormaliseKeepsWhatUrdfdomReads) {
  tinyxml2::XMLDocument doc;
  ASSERT_EQ(doc.Parse(R"(<robot name="r">
  <mujoco><compiler angle="degree"/></mujoco>
  <material name="m"><color rgba="0 0 1 1"/><color rgba="1 0 0 1"/></material>
  <link name="a">
    <inertial><mass value="1"/></inertial><inertial><mass value="2"/></inertial>
    <visual><origin xyz="1 0 0"/><origin xyz="2 0 0"/>
      <geometry><sphere radius="1"/><box size="1 1 1"/></geometry><geometry><box size="2 2 2"/></geometry>
      <material name="x"><color rgba="1 0 0"/></material><material name="y"/></visual>
    <visual><geometry><box size="3 3 3"/></geometry></visual>
    <collision><geometry><box size="4 4 4"/></geometry></collision>
  </link>
  <link name="b"/>
  <joint name="j" type="continuous"><parent link="a"/><child link="b"/>
    <axis xyz="0 0 1"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="2" velocity="1"/></joint>
  <gazebo reference="a"><material>Gazebo/Red</material></gazebo>
  <transmission name="t"><joint name="j"/></transmission>
</robot>)"),
            tinyxml2::XML_SUCCESS);
  normalise_urdf(doc.RootElement());
  EXPECT_EQ(text_of(doc.RootElement()),
            "<robot name=\"r\">"
            "<material name=\"m\"><color rgba=\"0 0 1 1\"/></material>"
            "<link name=\"a\"><inertial><mass value=\"1\"/></inertial>"
            "<visual><origin xyz=\"1 0 0\"/><geometry><sphere radius=\"1\"/></geometry>"
            "<material name=\"x\"/></visual>"
            "<visual><geometry><box size=\"3 3 3\"/></geometry></visual>"
            "<collision><geometry><box size=\"4 4 4\"/></geometry></collision></link>"
            "<link name=\"b\"/>"
            "<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/>"
            "<axis xyz=\"0 0 1\"/><limit effort=\"2\" velocity=\"1\"/></joint></robot>");
}

TEST(UrdfPrepare, ParsesMujocosErrorText) {
  MujocoError e =
      parse_mujoco_error("XML Error: repeated element: 'origin'\nElement 'origin', line 12\n");
  EXPECT_EQ(e.what, "repeated element: 'origin'");
  EXPECT_EQ(e.element, "origin");
  EXPECT_EQ(e.line, 12);
  e = parse_mujoco_error(
      "Error: mass and inertia of moving bodies must be larger than mjMINVAL\n"
      "Object name = l1, id = 2");
  EXPECT_EQ(e.what, "mass and inertia of moving bodies must be larger than mjMINVAL");
  EXPECT_EQ(e.object, "l1");
  EXPECT_EQ(e.line, 0);
}

// A real MuJoCo error about the prepared copy: an element repeated on its
// line of the copy (lines unchanged) is reported at that line, which
// retell() turns into the line of the user's file.
TEST(UrdfPrepare, MujocoErrorsAreRetoldAtTheUsersLine) {
  test_support::ScratchDir dir("urdf_prepare_retell");
  const auto urdf = dir.write("user.urdf", R"(<?xml version="1.0"?>
<!-- The user's file: comments and blank lines the copy does not keep. -->

<robot name="r">

  <link name="base_link"/>
  <joint name="j" type="fixed">
    <parent link="base_link"/>
    <child link="tool"/>
    <origin xyz="0 0 1"/>
  </joint>
  <link name="tool"/>
</robot>
)");
  const UrdfInfo info = prepare_urdf(urdf, {}, dir.path());
  std::ifstream in(info.prepared_urdf);
  std::stringstream copy;
  copy << in.rdbuf();
  std::string text = copy.str();
  const std::string origin = "<origin xyz=\"0 0 1\"/>";
  ASSERT_NE(text.find(origin), std::string::npos) << text;
  text.replace(text.find(origin), origin.size(), origin + "<origin/>");
  std::ofstream(info.prepared_urdf) << text;

  char error[1024] = "";
  mjModel* m = mj_loadXML(info.prepared_urdf.c_str(), nullptr, error, sizeof(error));
  ASSERT_EQ(m, nullptr);
  const std::string retold = info.retell(error);
  EXPECT_EQ(retold, urdf.string() +
                        ":10: MuJoCo 2.2 cannot load it: repeated element: 'origin' (element "
                        "<origin>)")
      << "MuJoCo said: " << error;
}

// Meshes as makers export them: a cube wound inside out and a cube without
// its top. The converted copy of the first is wound outward (what MuJoCo,
// culling back faces, needs), each file gets a notice naming it, and the
// open one has the camera draw both sides. A closed outward cube has none.
TEST(UrdfPrepare, MeshPartsInsideOutOrOpenAreTurnedAndNamed) {
  test_support::ScratchDir dir("urdf_prepare_mesh_parts");
  const char* cube_corners =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
  // Counter-clockwise seen from outside; the top is the second face.
  const char* faces[6] = {"1 4 3 2", "5 6 7 8", "1 2 6 5", "2 3 7 6", "3 4 8 7", "4 1 5 8"};
  std::string outward = cube_corners, inside_out = cube_corners, open = cube_corners;
  for (int f = 0; f < 6; ++f) {
    std::string reversed;
    std::istringstream corners(faces[f]);
    for (std::string c; corners >> c;) reversed = c + (reversed.empty() ? "" : " ") + reversed;
    outward += std::string("f ") + faces[f] + "\n";
    inside_out += "f " + reversed + "\n";
    if (f != 1) open += std::string("f ") + faces[f] + "\n";
  }
  dir.write("outward.obj", outward);
  dir.write("inside_out.obj", inside_out);
  dir.write("open.obj", open);
  auto urdf_with = [&](const std::string& mesh) {
    return dir.write(mesh + ".urdf", R"(<robot name="r">
  <link name="base_link"><visual><geometry><mesh filename=")" +
                                         mesh +
                                         R"(.obj" scale="0.1 0.1 0.1"/></geometry></visual></link>
</robot>)");
  };
  const UrdfInfo plain = prepare_urdf(urdf_with("outward"), {}, dir.path());
  EXPECT_TRUE(plain.notices.empty());
  EXPECT_FALSE(plain.open_visual_meshes);

  const UrdfInfo turned = prepare_urdf(urdf_with("inside_out"), {}, dir.path());
  ASSERT_EQ(turned.notices.size(), 1u);
  EXPECT_NE(turned.notices[0].find("inside_out.obj"), std::string::npos) << turned.notices[0];
  EXPECT_NE(turned.notices[0].find("1 wound inside out"), std::string::npos) << turned.notices[0];
  EXPECT_FALSE(turned.open_visual_meshes);
  // The converted binary STL MuJoCo reads encloses a positive volume.
  std::ifstream stl(dir.path() / "m0_inside_out.stl", std::ios::binary);
  ASSERT_TRUE(stl) << "no converted mesh";
  std::string bytes((std::istreambuf_iterator<char>(stl)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), 84u + 50u * 12u);
  double six_volume = 0;
  for (std::size_t at = 84; at < bytes.size(); at += 50) {
    float v[9];
    std::memcpy(v, bytes.data() + at + 12, sizeof v);
    const Eigen::Vector3d a(v[0], v[1], v[2]), b(v[3], v[4], v[5]), c(v[6], v[7], v[8]);
    six_volume += a.dot(b.cross(c));
  }
  EXPECT_NEAR(six_volume / 6, 1e-3, 1e-6);
  char error[1024] = "";
  mjModel* m = mj_loadXML(turned.prepared_urdf.c_str(), nullptr, error, sizeof(error));
  EXPECT_NE(m, nullptr) << error;
  mj_deleteModel(m);

  const UrdfInfo opened = prepare_urdf(urdf_with("open"), {}, dir.path());
  ASSERT_EQ(opened.notices.size(), 1u);
  EXPECT_NE(opened.notices[0].find("1 open"), std::string::npos) << opened.notices[0];
  EXPECT_TRUE(opened.open_visual_meshes);
}

}  // namespace
}  // namespace arttrack::sim
