// The robot's kinematic tree and link shapes, built once from a URDF and
// immutable afterwards (shared read-only between threads, like mjModel).
//
// Links are numbered in topological order: the URDF root is link 0 and every
// link's parent has a smaller index. Each non-root link carries the URDF
// joint that connects it to its parent. The movable joints are the degrees of
// freedom (DOFs) indexed 0..num_joints()-1: the URDF's revolute, continuous
// and prismatic joints in depth-first tree order (siblings ordered by joint
// name), then the six virtual camera joints. URDF mimic joints are not DOFs:
// they follow their leader (Link::mimic_dof).
//
// Virtual camera joints (Garcia Cifuentes et al. 2017, Sec. III): a chain of
// six joints injected in memory after the nominal camera frame, ending in a
// new frame "<camera_frame>_corrected":
//   camera_offset_x, _y, _z           prismatic along x, y, z (metres), then
//   camera_offset_roll, _pitch, _yaw  revolute about x, y, z (radians),
// so T_nominal_corrected = Trans(x, y, z) Rx(roll) Ry(pitch) Rz(yaw); all
// zero is no correction. They absorb camera extrinsic and head kinematic error.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "arttrack/tracker/mesh_loader.h"

namespace arttrack {

enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic };

// A set of links: one flag per link index.
using LinkSet = std::vector<bool>;

// How to build a RobotModel from a URDF.
struct RobotModelOptions {
  // Folders that resolve relative and package://NAME/rest mesh paths (each
  // folder is tried as <folder>/rest and <folder>/NAME/rest). The URDF's own
  // folder is always searched, first.
  std::vector<std::string> mesh_search_paths;
  // Nominal camera frame: a URDF link, optical convention (z forward, x right, y down).
  std::string camera_frame = "camera_optical_frame";
  // Inject the six virtual camera joints after camera_frame.
  bool add_virtual_camera_joints = true;
  // Tessellation of URDF cylinders (sides) and spheres (meridians; half as
  // many bands) in Link::mesh. The renderer draws them exactly
  // (RoundShape); the mesh stands for them where triangles are counted (the
  // hypothesis evaluator's cost estimate).
  int cylinder_segments = 32;
  int sphere_segments = 24;
};

// A URDF cylinder or sphere among a link's visuals. The renderer draws it
// exactly (depth_renderer.h), not its tessellation in Link::mesh: a coarse
// tessellation fixed to its link changes as a joint turns the shape about
// itself, which the true shape does not, and its facets told the likelihood
// about rotations the camera cannot see (docs/accuracy.md, "Exact cylinders
// and spheres").
struct RoundShape {
  enum class Kind { kCylinder, kSphere };
  Kind kind = Kind::kCylinder;
  // The shape's frame in the link frame: origin at its centre, z along a
  // cylinder's axis.
  Eigen::Isometry3d T_link_shape = Eigen::Isometry3d::Identity();
  double radius_m = 0;
  double length_m = 0;  // a cylinder's; 0 for a sphere
  // Its tessellation in Link::mesh: vertices [first_vertex, first_vertex +
  // num_vertices), triangles [first_triangle, first_triangle + num_triangles).
  int first_vertex = 0, num_vertices = 0;
  int first_triangle = 0, num_triangles = 0;
};

// `mesh`'s triangles but the round shapes' tessellations (drawn exactly, not
// as triangles), in mesh order, over all of `mesh`'s vertices.
TriangleMesh without_round_shapes(const TriangleMesh& mesh,
                                  const std::vector<RoundShape>& round_shapes);

// One link and the joint to its parent.
struct Link {
  std::string name;
  int parent = -1;  // parent link index, smaller than this link's; -1 for the root
  // The joint from the parent ("" for the root). Its frame is placed by
  // T_parent_joint (URDF origin: xyz, then R = Rz(yaw) Ry(pitch) Rx(roll)) and
  // moves the link by a rotation about / translation along `axis`.
  std::string joint_name;
  JointType joint_type = JointType::kFixed;
  Eigen::Isometry3d T_parent_joint = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit vector, joint frame
  int dof = -1;  // index of the joint's coordinate in q; -1 for a fixed or mimic joint
  // A URDF mimic joint has no coordinate of its own: its value is
  // mimic_multiplier * q[mimic_dof] + mimic_offset (chains of mimics resolved
  // to the free joint they end at). -1 for any other joint.
  int mimic_dof = -1;
  double mimic_multiplier = 1.0;
  double mimic_offset = 0.0;
  // All visual elements merged, in the link frame, metres (empty if none).
  TriangleMesh mesh;
  // The cylinders and spheres among them, in mesh order.
  std::vector<RoundShape> round_shapes;
  // What orient_parts() found in the link's mesh files, every use counted.
  // Back-face culling is only right for closed surfaces: with
  // RenderOptions::open_parts_both_sides a link with an open part is drawn
  // from both sides.
  MeshOrientation mesh_parts;
  bool has_open_parts() const { return mesh_parts.open_parts > 0; }
  // Levels of detail (RobotModel::with_simplified_meshes): coarser versions
  // of `mesh`'s triangles without the round shapes' (drawn exactly anyway),
  // in increasing min_range_m. The renderer draws the coarsest level whose
  // min_range_m the link's nearest point lies beyond, along the optical
  // axis (a pixel there covers as much more as the level's error grew).
  struct MeshLevel {
    double min_range_m = 0;
    TriangleMesh mesh;
  };
  std::vector<MeshLevel> coarser_meshes;
};

// ROS's package lookup without ROS: the folder of package `name` is `start`
// or one of its ancestors when its folder name is `name` or its package.xml
// names it, or a folder `name` inside one of them. Empty if none.
std::filesystem::path find_package_folder(const std::string& name,
                                          const std::filesystem::path& start);

// Throws InputError when `path` names a xacro file (.xacro): macros that
// ROS's xacro expands into a URDF; arttrack reads URDF only and says how to
// expand it.
void check_not_xacro(const std::string& path);

// The kinematic tree and shapes of a robot. Immutable after construction.
class RobotModel {
 public:
  // Parses a URDF file. Throws InputError naming the file (missing,
  // malformed, past a size limit of model_limits.h: links, joints, chain
  // depth, mesh triangles, bytes), a joint (unsupported type, zero axis, a
  // mimic of a missing or fixed joint, a cycle of mimics), a mesh and its
  // link (missing, unreadable) or the camera frame (absent).
  static RobotModel from_urdf_file(const std::string& path, const RobotModelOptions& options = {});
  // Parses URDF text; relative mesh paths resolve against base_dir first.
  // `file`, if given, is the file the text came from (e.g. with a camera
  // mount added in memory): messages name it as from_urdf_file's do.
  static RobotModel from_urdf_string(const std::string& xml, const std::string& base_dir,
                                     const RobotModelOptions& options = {},
                                     const std::string& file = "");

  int num_links() const { return int(links_.size()); }
  // Number of DOFs, virtual joints included: the size of q.
  int num_joints() const { return int(dof_names_.size()); }

  const Link& link(int link) const { return links_[link]; }
  const std::string& link_name(int link) const { return links_[link].name; }
  // Link index by name; throws InputError naming the link and the URDF.
  int link_index(const std::string& name) const;

  // DOF names in q order.
  const std::vector<std::string>& joint_names() const { return dof_names_; }
  const std::string& joint_name(int dof) const { return dof_names_[dof]; }
  // DOF index by name; throws InputError naming the joint and the URDF
  // (saying so when the joint exists but is fixed or a mimic).
  int joint_index(const std::string& name) const;
  JointType joint_type(int dof) const { return links_[dof_link_[dof]].joint_type; }
  // The link the DOF moves directly (its child link).
  int joint_child_link(int dof) const { return dof_link_[dof]; }
  bool is_virtual_joint(int dof) const { return dof >= num_joints() - num_virtual_; }
  // Position limits, radians or metres; +-infinity for continuous and virtual joints.
  double joint_lower(int dof) const { return dof_lower_[dof]; }
  double joint_upper(int dof) const { return dof_upper_[dof]; }

  // The corrected camera frame "<camera_frame>_corrected" (the nominal camera
  // frame when there are no virtual joints). The renderer's viewpoint.
  int camera_link() const { return camera_link_; }
  int nominal_camera_link() const { return nominal_camera_link_; }

  // The links whose pose depends on DOF `dof`: its child link's subtree and
  // the subtrees of the mimic joints that follow it.
  LinkSet links_moved_by(int dof) const;
  // Link `link` and every link below it in the tree (mimic joints aside: a
  // rigid motion of the link carries these).
  LinkSet links_below(int link) const;
  // The links that have a mesh.
  const std::vector<int>& links_with_geometry() const { return geometry_links_; }
  // Triangles the renderer draws: every link mesh, less the tessellations of
  // the cylinders and spheres (drawn exactly); or, for level > 0, those of
  // each link's level `level` of detail (its coarsest below it if it has
  // fewer).
  int num_drawn_triangles(int level = 0) const;
  // A copy whose link meshes are simplified to within max_error_m of the
  // originals (mesh_simplify.h); cylinders and spheres, drawn exactly, are
  // kept. With coarser_levels > 0, level k = 1, 2, ... of each link
  // (Link::coarser_meshes) is within 2^k max_error_m of the original and
  // drawn from 2^k nearest_range_m on: at twice the range, a pixel covers
  // twice as much, so the error stays the same share of a pixel. A level
  // that would remove less than a tenth of the finer one is left out.
  // Links, joints and their indices are those of this model, so its
  // KinematicsState and LinkSets serve the copy. max_error_m <= 0 keeps
  // every triangle. `error_m`, if given, receives the largest error measured
  // over the links at level 0 (SimplifiedMesh::error_m). `threads`: links
  // simplified at once, the largest first (the result is the same).
  RobotModel with_simplified_meshes(double max_error_m, double* error_m = nullptr,
                                    double nearest_range_m = 0, int coarser_levels = 0,
                                    int threads = 1) const;
  // Where the model came from ("URDF file 'x'" or "URDF text"), for messages.
  const std::string& source() const { return source_; }
  // The options it was built with.
  const RobotModelOptions& options() const { return options_; }

 private:
  RobotModel() = default;
  static RobotModel build(const std::string& xml, const std::string& base_dir,
                          const std::string& source, const RobotModelOptions& options);
  // Sets mimic_dof (and the chain's multiplier and offset) of mimic links.
  void resolve_mimics();
  // Adds to `links` every link below one of them (a parent's index is
  // smaller than its child's: one pass in order).
  void add_links_below(LinkSet& links) const;

  std::string source_;
  RobotModelOptions options_;
  std::vector<Link> links_;
  std::vector<std::string> dof_names_;
  std::vector<int> dof_link_;
  std::vector<double> dof_lower_, dof_upper_;
  std::vector<std::string> fixed_joint_names_;
  std::map<std::string, std::string> mimic_leader_;  // mimic joint -> the joint it names
  std::vector<int> geometry_links_;
  int num_virtual_ = 0;
  int camera_link_ = -1;
  int nominal_camera_link_ = -1;
};

// One line on the model's mesh files as orient_parts() found them, for a
// user bringing a robot, e.g. "1204 mesh parts: 2 turned outward (link_3,
// link_5), 1 open (gripper)"; "no mesh file" when the links are URDF
// primitives only.
std::string describe_mesh_parts(const RobotModel& model);

}  // namespace arttrack
