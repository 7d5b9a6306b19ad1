#include "arttrack/tracker/robot_model.h"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/mesh_simplify.h"
#include "arttrack/tracker/internal/non_finite.h"
#include "arttrack/tracker/model_limits.h"

namespace arttrack {
namespace {

namespace fs = std::filesystem;

// urdfdom reports why a parse failed only through console_bridge; collect
// those messages to put them in the exception instead of on stderr.
class CollectErrors : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    if (!errors.empty()) errors += "; ";
    errors += text;
  }
  std::string errors;
};

urdf::ModelInterfaceSharedPtr parse_urdf(const std::string& xml, const std::string& source) {
  check_urdf_text(xml, source);
  // The handler is process-wide state: one parse at a time.
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  CollectErrors collect;
  console_bridge::useOutputHandler(&collect);
  urdf::ModelInterfaceSharedPtr model;
  std::string exception;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    exception = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!model) {
    std::string why = !collect.errors.empty() ? collect.errors : exception;
    if (why.empty()) why = "not a valid URDF";
    throw InputError("cannot parse " + source + ": " + why);
  }
  return model;
}

// urdfdom's links hold their children by shared_ptr: the links of a loop
// (refused below) would keep each other alive forever. Empties every link's
// child list when the parsed model is done with, whatever happened.
class BreakLinkCycles {
 public:
  explicit BreakLinkCycles(urdf::ModelInterfaceSharedPtr model) : model_(std::move(model)) {}
  ~BreakLinkCycles() {
    for (auto& [name, link] : model_->links_) link->child_links.clear();
  }
  BreakLinkCycles(const BreakLinkCycles&) = delete;
  BreakLinkCycles& operator=(const BreakLinkCycles&) = delete;

 private:
  urdf::ModelInterfaceSharedPtr model_;
};

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return T;
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

bool package_xml_names(const fs::path& dir, const std::string& name) {
  std::ifstream in(dir / "package.xml");
  if (!in) return false;
  std::stringstream text;
  text << in.rdbuf();
  return text.str().find("<name>" + name + "</name>") != std::string::npos;
}

// The file a URDF mesh reference names: package://NAME/rest tries
// <folder>/rest and <folder>/NAME/rest for the URDF's folder and then each
// search folder, and last <package>/rest for the package folder
// find_package_folder finds from the URDF's folder; a relative path tries
// <folder>/path.
std::string resolve_mesh_path(const std::string& uri, const std::string& base_dir,
                              const std::vector<std::string>& search_paths, const std::string& link,
                              const std::string& source) {
  std::vector<std::string> folders;
  if (!base_dir.empty()) folders.push_back(base_dir);
  folders.insert(folders.end(), search_paths.begin(), search_paths.end());
  std::vector<fs::path> candidates;
  if (starts_with(uri, "package://")) {
    const std::string rest_with_package = uri.substr(10);
    const size_t slash = rest_with_package.find('/');
    const std::string package = rest_with_package.substr(0, slash);
    const std::string rest = slash == std::string::npos ? "" : rest_with_package.substr(slash + 1);
    for (const std::string& folder : folders) {
      candidates.push_back(fs::path(folder) / rest);
      candidates.push_back(fs::path(folder) / package / rest);
    }
    if (!base_dir.empty())
      if (const fs::path found = find_package_folder(package, fs::absolute(base_dir));
          !found.empty())
        candidates.push_back(found / rest);
  } else if (starts_with(uri, "file://")) {
    candidates.push_back(uri.substr(7));
  } else if (fs::path(uri).is_absolute()) {
    candidates.push_back(uri);
  } else {
    for (const std::string& folder : folders) candidates.push_back(fs::path(folder) / uri);
  }
  std::error_code ec;
  for (const fs::path& candidate : candidates) {
    if (fs::is_regular_file(candidate, ec)) return candidate.lexically_normal().string();
  }
  std::string tried;
  for (const fs::path& candidate : candidates) {
    tried += (tried.empty() ? "" : ", ") + candidate.string();
  }
  throw InputError("mesh '" + uri + "' of link '" + link + "' in " + source +
                   " not found (tried: " + tried + ")");
}

// A mesh file as loaded, its parts turned outward where they enclose a
// volume (orient_parts).
struct LoadedMesh {
  TriangleMesh mesh;
  MeshOrientation orientation;
};

// The triangle mesh of one URDF geometry element, in the element's frame.
// `orientation`: what orient_parts() found in a mesh file (nothing for a
// primitive, closed and outward by construction).
TriangleMesh geometry_mesh(const urdf::Geometry& geometry, const std::string& link,
                           const std::string& base_dir, const std::string& source,
                           const RobotModelOptions& options,
                           std::map<std::string, LoadedMesh>& file_cache, std::uint64_t& triangles,
                           Eigen::Vector3d& scale, MeshOrientation& orientation) {
  scale = Eigen::Vector3d::Ones();
  orientation = {};
  // Sizes the simulator refuses (MuJoCo: a geom size must be positive) would
  // render as nothing or as NaN here: refused alike, naming the link.
  auto positive = [&](const char* what, std::initializer_list<double> values) {
    for (const double v : values)
      if (!(v > 0) || !std::isfinite(v)) {
        std::ostringstream os;
        os << "link '" << link << "' in " << source << ": " << what << " has " << v
           << " (expected positive finite numbers)";
        throw InputError(os.str());
      }
  };
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      positive("box size", {box.dim.x, box.dim.y, box.dim.z});
      return make_box(Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z));
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      positive("cylinder radius and length", {cylinder.radius, cylinder.length});
      return make_cylinder(cylinder.radius, cylinder.length, options.cylinder_segments);
    }
    case urdf::Geometry::SPHERE: {
      const auto& sphere = static_cast<const urdf::Sphere&>(geometry);
      positive("sphere radius", {sphere.radius});
      return make_sphere(sphere.radius, options.sphere_segments);
    }
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
      scale = Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z);
      if (!scale.allFinite() || (scale.array() == 0).any())
        throw InputError("link '" + link + "' in " + source + ": mesh '" + mesh.filename +
                         "' has a zero or non-finite scale (expected finite, non-zero factors)");
      const std::string path =
          resolve_mesh_path(mesh.filename, base_dir, options.mesh_search_paths, link, source);
      // Every use counts: a binary STL's declared triangles before it is
      // read, any mesh's after.
      const std::string what =
          "mesh triangles (with mesh '" + mesh.filename + "' of link '" + link + "')";
      auto it = file_cache.find(path);
      if (it == file_cache.end()) {
        if (const auto declared = binary_stl_triangle_count(path))
          check_model_count(source, triangles + *declared, ModelLimits::kMaxMeshTriangles, what);
        try {
          LoadedMesh loaded{load_mesh(path), {}};
          loaded.orientation = orient_parts(loaded.mesh);
          it = file_cache.emplace(path, std::move(loaded)).first;
        } catch (const InputError& e) {
          throw InputError(std::string(e.what()) + " (mesh '" + mesh.filename + "' of link '" +
                           link + "' in " + source + ")");
        }
      }
      triangles += it->second.mesh.triangles.size();
      check_model_count(source, triangles, ModelLimits::kMaxMeshTriangles, what);
      orientation = it->second.orientation;
      return it->second.mesh;
    }
  }
  throw InputError("link '" + link + "' in " + source + " has a geometry of unknown type");
}

}  // namespace

void check_not_xacro(const std::string& path) {
  if (fs::path(path).extension() != ".xacro") return;
  throw InputError(path + ": a xacro file, not a URDF: expand it first, e.g. `xacro " + path +
                   " > robot.urdf` (ROS's xacro package), and give arttrack the URDF");
}

std::string describe_mesh_parts(const RobotModel& model) {
  MeshOrientation total;
  std::string turned, open;
  for (int l = 0; l < model.num_links(); ++l) {
    const Link& link = model.link(l);
    total += link.mesh_parts;
    if (link.mesh_parts.turned_parts > 0) turned += (turned.empty() ? "" : ", ") + link.name;
    if (link.mesh_parts.open_parts > 0) open += (open.empty() ? "" : ", ") + link.name;
  }
  if (total.parts == 0) return "no mesh file";
  std::string out = std::to_string(total.parts) +
                    " mesh parts: " + std::to_string(total.turned_parts) + " turned outward";
  if (!turned.empty()) out += " (" + turned + ")";
  out += ", " + std::to_string(total.open_parts) + " open";
  if (!open.empty()) out += " (" + open + ")";
  return out;
}

fs::path find_package_folder(const std::string& name, const fs::path& start) {
  for (fs::path d = start; !d.empty(); d = d.parent_path()) {
    if (d.filename() == name || package_xml_names(d, name)) return d;
    std::error_code ec;
    if (fs::is_directory(d / name, ec)) return d / name;
    if (d == d.parent_path()) break;
  }
  return {};
}

RobotModel RobotModel::from_urdf_file(const std::string& path, const RobotModelOptions& options) {
  check_not_xacro(path);
  const std::string source = "URDF file '" + path + "'";
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError(source + " does not exist or is not a file");
  }
  check_urdf_file_size(path);
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) throw InputError("cannot read " + source);
  return build(text.str(), fs::path(path).parent_path().string(), source, options);
}

RobotModel RobotModel::from_urdf_string(const std::string& xml, const std::string& base_dir,
                                        const RobotModelOptions& options, const std::string& file) {
  return build(xml, base_dir, file.empty() ? "URDF text" : "URDF file '" + file + "'", options);
}

RobotModel RobotModel::build(const std::string& xml, const std::string& base_dir,
                             const std::string& source, const RobotModelOptions& options) {
  const urdf::ModelInterfaceSharedPtr urdf_model = parse_urdf(xml, source);
  const BreakLinkCycles release(urdf_model);
  // Bounds before cost: the tree's size, then its depth.
  check_model_count(source, urdf_model->links_.size(), ModelLimits::kMaxLinks, "links");
  check_model_count(source, urdf_model->joints_.size(), ModelLimits::kMaxJoints, "joints");
  {
    std::map<std::string, std::string> parent_of;  // child link -> parent link
    for (const auto& [name, joint] : urdf_model->joints_)
      parent_of.emplace(joint->child_link_name, joint->parent_link_name);
    check_chain_depth(source, parent_of);
  }
  std::uint64_t triangles = 0;  // of the meshes, against ModelLimits::kMaxMeshTriangles
  RobotModel model;
  model.source_ = source;
  model.options_ = options;
  std::map<std::string, LoadedMesh> file_cache;

  // A link that is the child of two joints closes a kinematic loop: the walk
  // below would never end.
  std::map<std::string, std::string> parent_joint;  // link -> its joint
  for (const auto& [name, joint] : urdf_model->joints_) {
    if (const auto [it, added] = parent_joint.emplace(joint->child_link_name, name); !added)
      throw InputError(source + ": link '" + joint->child_link_name + "' is the child of joints '" +
                       it->second + "' and '" + name + "'; a URDF is a tree (no kinematic loops)");
  }

  // Depth-first walk from the root: link indices in preorder, so every
  // parent precedes its children and each subtree is a contiguous range.
  struct Pending {
    urdf::LinkConstSharedPtr link;
    int parent;
  };
  std::vector<Pending> stack{{urdf_model->getRoot(), -1}};
  while (!stack.empty()) {
    const Pending item = stack.back();
    stack.pop_back();
    const urdf::Link& ulink = *item.link;
    Link link;
    link.name = ulink.name;
    link.parent = item.parent;
    if (item.parent >= 0) {
      const urdf::Joint& joint = *ulink.parent_joint;
      link.joint_name = joint.name;
      link.T_parent_joint = to_isometry(joint.parent_to_joint_origin_transform);
      switch (joint.type) {
        case urdf::Joint::FIXED:
          link.joint_type = JointType::kFixed;
          break;
        case urdf::Joint::REVOLUTE:
          link.joint_type = JointType::kRevolute;
          break;
        case urdf::Joint::CONTINUOUS:
          link.joint_type = JointType::kContinuous;
          break;
        case urdf::Joint::PRISMATIC:
          link.joint_type = JointType::kPrismatic;
          break;
        case urdf::Joint::FLOATING:
        case urdf::Joint::PLANAR:
        default:
          throw InputError("joint '" + joint.name + "' in " + source +
                           " has an unsupported type (floating or planar); use revolute, "
                           "continuous, prismatic or fixed");
      }
      if (link.joint_type == JointType::kFixed) {
        model.fixed_joint_names_.push_back(joint.name);
      } else if (joint.mimic) {
        // Resolved to a DOF once all joints are known (resolve_mimics).
        const Eigen::Vector3d axis(joint.axis.x, joint.axis.y, joint.axis.z);
        if (!(axis.norm() > 1e-12) || !axis.allFinite()) {
          throw InputError("joint '" + joint.name + "' in " + source + " has a zero axis");
        }
        link.axis = axis.normalized();
        link.mimic_multiplier = joint.mimic->multiplier;
        link.mimic_offset = joint.mimic->offset;
        model.mimic_leader_[joint.name] = joint.mimic->joint_name;
      } else {
        const Eigen::Vector3d axis(joint.axis.x, joint.axis.y, joint.axis.z);
        if (!(axis.norm() > 1e-12) || !axis.allFinite()) {
          throw InputError("joint '" + joint.name + "' in " + source + " has a zero axis");
        }
        link.axis = axis.normalized();
        link.dof = int(model.dof_names_.size());
        model.dof_names_.push_back(joint.name);
        model.dof_link_.push_back(int(model.links_.size()));
        const bool limited = link.joint_type != JointType::kContinuous && joint.limits;
        if (limited && !(joint.limits->lower <= joint.limits->upper)) {
          std::ostringstream os;
          os << "joint '" << joint.name << "' in " << source << ": limit lower "
             << joint.limits->lower << " > upper " << joint.limits->upper
             << " (expected lower <= upper)";
          throw InputError(os.str());
        }
        model.dof_lower_.push_back(limited ? joint.limits->lower : -kInf);
        model.dof_upper_.push_back(limited ? joint.limits->upper : kInf);
      }
    }
    // All visual elements, each placed by its origin, merged into one mesh.
    std::vector<urdf::VisualSharedPtr> visuals = ulink.visual_array;
    if (visuals.empty() && ulink.visual) visuals.push_back(ulink.visual);
    for (const urdf::VisualSharedPtr& visual : visuals) {
      if (!visual || !visual->geometry) continue;
      Eigen::Vector3d scale;
      MeshOrientation orientation;
      const TriangleMesh part = geometry_mesh(*visual->geometry, ulink.name, base_dir, source,
                                              options, file_cache, triangles, scale, orientation);
      link.mesh_parts += orientation;
      const Eigen::Isometry3d T_link_visual = to_isometry(visual->origin);
      Eigen::Affine3d T_link_part(T_link_visual);
      const int type = visual->geometry->type;
      if (type == urdf::Geometry::CYLINDER || type == urdf::Geometry::SPHERE) {
        RoundShape shape;
        shape.T_link_shape = T_link_visual;
        if (type == urdf::Geometry::CYLINDER) {
          const auto& cylinder = static_cast<const urdf::Cylinder&>(*visual->geometry);
          shape.kind = RoundShape::Kind::kCylinder;
          shape.radius_m = cylinder.radius;
          shape.length_m = cylinder.length;
        } else {
          shape.kind = RoundShape::Kind::kSphere;
          shape.radius_m = static_cast<const urdf::Sphere&>(*visual->geometry).radius;
        }
        shape.first_vertex = int(link.mesh.vertices_m.size());
        shape.num_vertices = int(part.vertices_m.size());
        shape.first_triangle = int(link.mesh.triangles.size());
        shape.num_triangles = int(part.triangles.size());
        link.round_shapes.push_back(shape);
      }
      T_link_part.linear() = T_link_part.linear() * scale.asDiagonal();
      link.mesh.append(part, T_link_part);
    }
    const int index = int(model.links_.size());
    model.links_.push_back(std::move(link));

    // Children in joint-name order, pushed reversed so the first pops first.
    std::vector<urdf::JointSharedPtr> children = ulink.child_joints;
    std::sort(children.begin(), children.end(),
              [](const auto& a, const auto& b) { return a->name < b->name; });
    for (auto it = children.rbegin(); it != children.rend(); ++it) {
      stack.push_back({urdf_model->getLink((*it)->child_link_name), index});
    }
  }
  // Links whose joints form a loop apart from the tree: each has a parent,
  // so urdfdom finds one root, but the walk never reaches them.
  if (model.links_.size() != urdf_model->links_.size()) {
    for (const auto& entry : urdf_model->links_) {
      const std::string& name = entry.first;  // (clang 14 lambdas capture no bindings)
      const auto reached = [&](const Link& l) { return l.name == name; };
      if (std::none_of(model.links_.begin(), model.links_.end(), reached))
        throw InputError(source + ": link '" + name + "' is not connected to the root link '" +
                         model.links_.front().name +
                         "' (its joints form a loop); a URDF is a tree (no kinematic loops)");
    }
  }

  model.resolve_mimics();

  if (!options.camera_frame.empty()) {
    auto it = std::find_if(model.links_.begin(), model.links_.end(),
                           [&](const Link& l) { return l.name == options.camera_frame; });
    if (it == model.links_.end()) {
      throw InputError("camera frame '" + options.camera_frame + "' is not a link of " + source);
    }
    model.nominal_camera_link_ = int(it - model.links_.begin());
    model.camera_link_ = model.nominal_camera_link_;
  }
  if (options.add_virtual_camera_joints) {
    if (options.camera_frame.empty()) {
      throw InputError("virtual camera joints need a camera frame (" + source + ")");
    }
    // Virtual chain appended after all URDF links: parents still come first.
    const std::string cam = options.camera_frame;
    const char* suffixes[6] = {"x", "y", "z", "roll", "pitch", "yaw"};
    int parent = model.nominal_camera_link_;
    for (int k = 0; k < 6; ++k) {
      Link link;
      link.name = k < 5 ? cam + "_offset_" + suffixes[k] : cam + "_corrected";
      link.joint_name = std::string("camera_offset_") + suffixes[k];
      for (const Link& other : model.links_) {
        if (other.name == link.name || other.joint_name == link.joint_name) {
          throw InputError(source + " already has a link or joint named '" +
                           (other.name == link.name ? link.name : link.joint_name) +
                           "', reserved for the virtual camera joints");
        }
      }
      link.parent = parent;
      link.joint_type = k < 3 ? JointType::kPrismatic : JointType::kRevolute;
      link.axis = Eigen::Vector3d::Unit(k % 3);
      link.dof = int(model.dof_names_.size());
      model.dof_names_.push_back(link.joint_name);
      model.dof_link_.push_back(int(model.links_.size()));
      model.dof_lower_.push_back(-kInf);
      model.dof_upper_.push_back(kInf);
      parent = int(model.links_.size());
      model.links_.push_back(std::move(link));
    }
    model.num_virtual_ = 6;
    model.camera_link_ = parent;
  }
  for (int l = 0; l < model.num_links(); ++l) {
    if (!model.links_[l].mesh.empty()) model.geometry_links_.push_back(l);
  }
  return model;
}

void RobotModel::resolve_mimics() {
  for (Link& link : links_) {
    const auto first = mimic_leader_.find(link.joint_name);
    if (first == mimic_leader_.end()) continue;
    // Follow the chain to a free joint: q = m_k (... (m_1 q_leader + o_1) ...) + o_k.
    std::string leader = first->second;
    for (size_t steps = 0; mimic_leader_.count(leader); ++steps) {
      if (steps >= mimic_leader_.size()) {
        throw InputError("mimic joint '" + link.joint_name + "' in " + source_ +
                         " is part of a cycle of mimics; one of them must be a free joint");
      }
      const Link& l = *std::find_if(links_.begin(), links_.end(),
                                    [&](const Link& x) { return x.joint_name == leader; });
      link.mimic_offset += link.mimic_multiplier * l.mimic_offset;
      link.mimic_multiplier *= l.mimic_multiplier;
      leader = mimic_leader_.at(leader);
    }
    const auto dof = std::find(dof_names_.begin(), dof_names_.end(), leader);
    if (dof == dof_names_.end()) {
      throw InputError("mimic joint '" + link.joint_name + "' in " + source_ + " follows '" +
                       leader +
                       "', which is not a revolute, continuous or prismatic joint of the URDF");
    }
    link.mimic_dof = int(dof - dof_names_.begin());
  }
}

int RobotModel::link_index(const std::string& name) const {
  for (int l = 0; l < num_links(); ++l) {
    if (links_[l].name == name) return l;
  }
  throw InputError("unknown link '" + name + "' in robot model from " + source_);
}

int RobotModel::joint_index(const std::string& name) const {
  for (int j = 0; j < num_joints(); ++j) {
    if (dof_names_[j] == name) return j;
  }
  if (std::find(fixed_joint_names_.begin(), fixed_joint_names_.end(), name) !=
      fixed_joint_names_.end()) {
    throw InputError("joint '" + name + "' in " + source_ + " is fixed, not a degree of freedom");
  }
  if (const auto it = mimic_leader_.find(name); it != mimic_leader_.end()) {
    throw InputError("joint '" + name + "' in " + source_ + " is a mimic of '" + it->second +
                     "', not a degree of freedom");
  }
  throw InputError("unknown joint '" + name + "' in robot model from " + source_);
}

TriangleMesh without_round_shapes(const TriangleMesh& mesh,
                                  const std::vector<RoundShape>& round_shapes) {
  TriangleMesh out;
  out.vertices_m = mesh.vertices_m;
  std::size_t next_shape = 0;
  for (int t = 0; t < int(mesh.triangles.size()); ++t) {
    if (next_shape < round_shapes.size() && t == round_shapes[next_shape].first_triangle) {
      t += round_shapes[next_shape++].num_triangles - 1;
      continue;
    }
    out.triangles.push_back(mesh.triangles[std::size_t(t)]);
  }
  return out;
}

int RobotModel::num_drawn_triangles(int level) const {
  int count = 0;
  for (const Link& link : links_) {
    if (level > 0 && !link.coarser_meshes.empty()) {
      const std::size_t k = std::min(std::size_t(level), link.coarser_meshes.size());
      count += int(link.coarser_meshes[k - 1].mesh.triangles.size());
      continue;
    }
    count += int(link.mesh.triangles.size());
    for (const RoundShape& shape : link.round_shapes) count -= shape.num_triangles;
  }
  return count;
}

RobotModel RobotModel::with_simplified_meshes(double max_error_m, double* error_m,
                                              double nearest_range_m, int coarser_levels,
                                              int threads) const {
  RobotModel out = *this;
  // One link's levels; returns the error measured at level 0.
  auto simplify_link = [&](Link& link) {
    // The triangles drawn as triangles, simplified together; then each round
    // shape's tessellation (its vertices and triangles are its own) after them.
    SimplifiedMesh simplified =
        simplify_mesh(without_round_shapes(link.mesh, link.round_shapes), max_error_m);
    const double level_0_error_m = simplified.error_m;
    // Each level from the last one kept, within the error it may add: 2^k e
    // in all (the distances add up along the chain). A level that would
    // remove less than a tenth is left out (the finer one serves its range).
    link.coarser_meshes.clear();
    const TriangleMesh* finer = &simplified.mesh;
    double finer_error_m = max_error_m;
    for (int k = 1; k <= coarser_levels && !finer->empty(); ++k) {
      const double level_error_m = double(1 << k) * max_error_m;
      SimplifiedMesh coarser = simplify_mesh(*finer, level_error_m - finer_error_m);
      if (10 * coarser.mesh.triangles.size() > 9 * finer->triangles.size()) continue;
      link.coarser_meshes.push_back({double(1 << k) * nearest_range_m, std::move(coarser.mesh)});
      finer = &link.coarser_meshes.back().mesh;
      finer_error_m = level_error_m;
    }
    TriangleMesh rebuilt = std::move(simplified.mesh);
    for (RoundShape& shape : link.round_shapes) {
      TriangleMesh part;
      part.vertices_m.assign(
          link.mesh.vertices_m.begin() + shape.first_vertex,
          link.mesh.vertices_m.begin() + shape.first_vertex + shape.num_vertices);
      for (int t = 0; t < shape.num_triangles; ++t)
        part.triangles.push_back(link.mesh.triangles[std::size_t(shape.first_triangle + t)] -
                                 Eigen::Vector3i::Constant(shape.first_vertex));
      shape.first_vertex = int(rebuilt.vertices_m.size());
      shape.first_triangle = int(rebuilt.triangles.size());
      rebuilt.append(part);
    }
    link.mesh = std::move(rebuilt);
    return level_0_error_m;
  };
  // Links are independent: the largest first, each to the next free thread
  // (the result does not depend on the threads).
  std::vector<int> order;
  for (int l = 0; l < int(out.links_.size()); ++l)
    if (!out.links_[std::size_t(l)].mesh.empty() && max_error_m > 0) order.push_back(l);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return out.links_[std::size_t(a)].mesh.triangles.size() >
           out.links_[std::size_t(b)].mesh.triangles.size();
  });
  std::vector<double> errors(out.links_.size(), 0.0);
  std::atomic<int> next{0};
  std::mutex failure_mutex;
  std::exception_ptr failure;
  auto work = [&] {
    for (int k = next++; k < int(order.size()); k = next++) {
      try {
        errors[std::size_t(order[std::size_t(k)])] =
            simplify_link(out.links_[std::size_t(order[std::size_t(k)])]);
      } catch (...) {
        std::lock_guard lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < std::min(threads, int(order.size())); ++t) helpers.emplace_back(work);
  work();
  for (std::thread& h : helpers) h.join();
  if (failure) std::rethrow_exception(failure);
  if (error_m) *error_m = errors.empty() ? 0.0 : *std::max_element(errors.begin(), errors.end());
  return out;
}

void RobotModel::add_links_below(LinkSet& links) const {
  for (int l = 1; l < num_links(); ++l)
    if (links[links_[l].parent]) links[l] = true;
}

LinkSet RobotModel::links_moved_by(int dof) const {
  LinkSet moved(links_.size(), false);
  moved[dof_link_[dof]] = true;
  for (int l = 1; l < num_links(); ++l)
    if (links_[l].mimic_dof == dof) moved[l] = true;
  add_links_below(moved);
  return moved;
}

LinkSet RobotModel::links_below(int link) const {
  LinkSet below(links_.size(), false);
  below[link] = true;
  add_links_below(below);
  return below;
}

}  // namespace arttrack
