// Turns a user's URDF into one MuJoCo 2.2 loads as intended, in a work
// directory (the user's file is never changed): a <mujoco><compiler/> block
// that keeps visual geometry and fixed links, and every mesh rewritten as a
// uniquely named binary STL with its scale baked in; links without an
// <inertial> get one derived from their geometry.
#pragma once

#include <Eigen/Geometry>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

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
};

// Parses `urdf`, resolves every mesh (package://NAME/... through
// `package_paths`, else a folder NAME among the URDF's ancestors or next to
// them; relative paths against the URDF's folder), converts the meshes and
// writes the prepared URDF into `work_dir`. Errors (missing file, malformed
// XML, missing mesh, unknown package): InputError naming the URDF and item.
UrdfInfo prepare_urdf(const std::filesystem::path& urdf,
                      const std::map<std::string, std::filesystem::path>& package_paths,
                      const std::filesystem::path& work_dir);

// Resolves a URDF mesh file name (package://, file://, relative, absolute).
// Returns an empty path if a package is unknown.
std::filesystem::path resolve_mesh_path(
    const std::string& filename, const std::filesystem::path& urdf_dir,
    const std::map<std::string, std::filesystem::path>& package_paths);

}  // namespace arttrack::sim
