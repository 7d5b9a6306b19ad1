// Turns a user's URDF into one MuJoCo 2.2 loads as intended, in a work
// directory (the user's file is never changed):
// - the robot urdfdom (ROS, and the tracker) reads: what urdfdom tolerates
//   and MuJoCo refuses is normalised the way urdfdom reads it
//   (normalise_urdf);
// - a <mujoco><compiler/> block that keeps visual geometry and fixed links;
// - every mesh rewritten as uniquely named binary STL files with its scale
//   baked in (split into parts of at most 200 000 triangles, MuJoCo 2.2's
//   limit per file);
// - links without a usable <inertial> get one derived from their geometry.
// Errors name the user's file and, for an element of it, its line there.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "arttrack/sim/urdf_perturbation.h"
#include "urdf_xml.h"  // tinyxml2's declarations

namespace arttrack::sim {

// What the model builder needs to know of the URDF besides MuJoCo's view.
struct UrdfInfo {
  std::filesystem::path source;         // the user's URDF
  std::filesystem::path prepared_urdf;  // the rewritten copy in the work dir
  std::string root_link;
  std::vector<std::string> link_names;  // document order
  // Joints with a degree of freedom a servo can drive (revolute, continuous,
  // prismatic; not mimic), in document order.
  std::vector<std::string> joint_names;
  std::map<std::string, double> joint_effort;  // URDF effort limit (0: none)
  // Origin of each link relative to its parent (its parent joint's origin),
  // at full double precision.
  std::map<std::string, Eigen::Isometry3d> T_parent_link;
  std::map<std::string, Eigen::Vector3d> joint_axis;  // unit vectors
  // URDF mimic joints: q_joint = multiplier q_leader + offset. MuJoCo 2.2
  // ignores <mimic>; the builder turns them into joint equality constraints.
  struct Mimic {
    std::string joint, leader;
    double multiplier = 1, offset = 0;
  };
  std::vector<Mimic> mimics;
  // Links without <inertial> given one in the prepared copy: mass and
  // inertia from their geometry (solid boxes, cylinders and spheres of
  // 1000 kg/m^3), or 0.01 kg at the origin for a link without such geometry
  // that moves on its own (a welded frame stays massless).
  std::vector<std::string> links_with_derived_inertia;
  // Of those, the moving links whose own <inertial> MuJoCo would refuse
  // (mass or an inertia eigenvalue not positive, nothing welded to them
  // with mass): link -> why.
  std::map<std::string, std::string> unusable_inertials;
  // A visual mesh has an open part (orient_parts()): the depth camera then
  // draws both sides of every surface, as MuJoCo's back-face culling would
  // show the far side or nothing there.
  bool open_visual_meshes = false;
  // What the simulator left out or changed that the user should know
  // ("<source>:<line>: ..."), e.g. a collision shape without volume.
  std::vector<std::string> notices;
  // Line in the user's file of the element at each line of the prepared
  // copy (elements arttrack added are missing).
  std::map<int, int> source_line;

  // MuJoCo's message about the prepared copy retold about the user's file:
  // "<source>:<line>: MuJoCo 2.2 cannot load it: <what> (element <name>)",
  // the line being the element's in the user's file.
  std::string retell(const std::string& mujoco_error) const;
};

// MuJoCo's error text split into its parts: "XML Error: <what>\nElement
// '<element>', line <line>" or "Error: <what>\nObject name = <object>, id =
// <k>" (line 0, names empty where absent).
struct MujocoError {
  std::string what, element, object;
  int line = 0;
};
MujocoError parse_mujoco_error(const std::string& text);

// Normalises a parsed URDF in place to what urdfdom reads of it, in forms
// MuJoCo 2.2 reads the same way:
// - under <robot>, only <link>, <joint> and <material> stay (<gazebo>,
//   <transmission>, <ros2_control>, <sensor>, a <mujoco> block, leftover
//   xacro elements: none is part of urdfdom's model);
// - a repeated element where urdfdom reads one keeps the first, as urdfdom
//   does (two <material>, <origin> or <geometry> in a <visual>, two
//   <inertial>, two <axis> or <limit> in a joint, two <color> in a
//   material...; MuJoCo refuses every repeat): only <link>, <joint>,
//   <material> under <robot> and <visual>, <collision> in a <link> repeat;
// - a <geometry> keeps its first shape only (urdfdom's; MuJoCo would take a
//   <box> anywhere in it first);
// - a <color> whose rgba is not four numbers in [0, 1] is dropped (urdfdom
//   ignores it in a <visual>; MuJoCo refuses the file);
// - a continuous joint's <limit> loses lower and upper (urdfdom's model and
//   the tracker ignore them; MuJoCo would limit the joint).
// (prepare_urdf also leaves out collision shapes without volume, which
// collide with nothing in ROS and which MuJoCo refuses, with a notice.)
void normalise_urdf(tinyxml2::XMLElement* robot);

// Parses `urdf`, normalises it (normalise_urdf), applies `perturbation`
// (the scene's camera mount, a scenario's miscalibration), checks its size
// (model_limits.h), resolves every mesh (package://NAME/... through
// `package_paths`, else find_package_folder from the URDF's folder; relative
// paths against the URDF's folder), converts the meshes and writes the
// prepared URDF into `work_dir`. Errors (missing file, malformed XML, past a
// size limit, a floating or planar joint, missing mesh, unknown package):
// InputError naming the user's URDF, the item and its line there.
UrdfInfo prepare_urdf(const std::filesystem::path& urdf,
                      const std::map<std::string, std::filesystem::path>& package_paths,
                      const std::filesystem::path& work_dir,
                      const UrdfPerturbation& perturbation = {});

}  // namespace arttrack::sim
