#include "arttrack/sim/scene.h"

#include <cmath>

#include "arttrack/sim/internal/config_geometry.h"
#include "arttrack/sim/search_paths.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/units.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {
namespace fs = std::filesystem;

namespace {

// `position_m: [x, y, z]` and `rpy_deg: [roll, pitch, yaw]` (optional).
Eigen::Isometry3d pose(const ConfigNode& n) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = vec<3>(n, "position_m", Eigen::Vector3d::Zero());
  T.linear() = rpy_matrix(kRadPerDeg * vec<3>(n, "rpy_deg", Eigen::Vector3d::Zero()));
  return T;
}

Eigen::Vector4f rgba(const ConfigNode& n, const Eigen::Vector4f& fallback) {
  const Eigen::Vector4d c = vec<4>(n, "rgba", fallback.cast<double>());
  for (int i = 0; i < 4; ++i)
    if (c[i] < 0 || c[i] > 1) n.fail("rgba", "must hold numbers in [0, 1]");
  return c.cast<float>();
}

double length(const ConfigNode& n, const std::string& key) {
  return n.required_number(key, 1e-4, 100.0);
}

// A path from the scene file: relative to the file, else to a search folder
// (search_paths.h).
fs::path resolve(const ConfigNode& n, const std::string& key, const fs::path& scene_dir,
                 bool must_exist) {
  std::error_code ec;  // a name too long for the system is no file, not an exception
  const fs::path p = n.required<std::string>(key);
  if (p.is_absolute()) {
    if (must_exist && !fs::exists(p, ec))
      n.fail(key, "= " + quote_value(p.string()) + ": no such file");
    return p;
  }
  const fs::path next_to_scene = scene_dir / p;
  if (fs::exists(next_to_scene, ec)) return fs::weakly_canonical(next_to_scene);
  if (const std::optional<fs::path> found = find_in_search_dirs(p))
    return fs::weakly_canonical(*found);
  if (must_exist)
    n.fail(key, "= " + quote_value(p.string()) + ": no such file next to the scene (in " +
                    scene_dir.string() + ") or in the search folders (" + search_dirs_text() + ")");
  return next_to_scene;
}

void read_robot(const ConfigNode& n, const fs::path& dir, SceneDescription& s) {
  s.urdf_path = resolve(n, "urdf", dir, true);
  try {
    check_not_xacro(s.urdf_path.string());
  } catch (const InputError& e) {
    n.fail("urdf", std::string("names ") + e.what());
  }
  const ConfigNode packages = n.child("packages");
  for (const std::string& name : packages.keys()) {
    const fs::path root = resolve(packages, name, dir, true);
    s.package_paths[name] = root;
  }
  if (n.has("initial_joints_deg") && n.has("initial_joints_rad"))
    n.fail("initial_joints_rad", "cannot be given together with initial_joints_deg");
  for (const auto& [key, scale] : {std::pair<std::string, double>{"initial_joints_deg", kRadPerDeg},
                                   {"initial_joints_rad", 1.0}}) {
    const ConfigNode joints = n.child(key);
    for (const std::string& name : joints.keys())
      s.initial_joints_rad[name] = scale * joints.required_number(name, -1e4, 1e4);
  }
  s.end_effector_links = n.get<std::vector<std::string>>("end_effectors", s.end_effector_links);
  // Members are joints or groups declared before.
  const ConfigNode groups = n.child("groups");
  for (const std::string& name : groups.keys()) {
    if (name == "all") groups.fail(name, "is always every movable joint: choose another name");
    std::vector<std::string> members;
    try {
      members = groups.required<std::vector<std::string>>(name);
    } catch (const InputError&) {
      groups.fail(name, "must be a list of joint names (or groups declared before it)");
    }
    if (members.empty()) groups.fail(name, "must name at least one joint");
    std::vector<std::string>& joints = s.joint_groups[name];
    for (const std::string& m : members) {
      const auto it = s.joint_groups.find(m);
      if (it != s.joint_groups.end() && m != name)
        joints.insert(joints.end(), it->second.begin(), it->second.end());
      else
        joints.push_back(m);
    }
  }
  const ConfigNode tracker = n.child("tracker_overrides");
  for (const std::string& key : tracker.keys())
    s.tracker_overrides.emplace_back(key, tracker.flow_text(key));
}

// `look_at_m`: the optical axis (z) towards that point, x right and level
// (perpendicular to the world's z), y down.
Eigen::Matrix3d look_at(const ConfigNode& n, const Eigen::Vector3d& from_m) {
  const Eigen::Vector3d z = vec<3>(n, "look_at_m", Eigen::Vector3d::Zero()) - from_m;
  if (z.norm() < 1e-6) n.fail("look_at_m", "must differ from position_m");
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6 * z.norm())
    n.fail("look_at_m", "looks straight up or down; give rpy_deg instead");
  Eigen::Matrix3d R;
  R.col(2) = z.normalized();
  R.col(0) = x.normalized();
  R.col(1) = R.col(2).cross(R.col(0));
  return R;
}

void read_camera_mount(const ConfigNode& n, SceneDescription& s) {
  CameraMount mount;
  mount.parent_link = n.get<std::string>("parent", "world");
  if (mount.parent_link.empty()) n.fail("parent", "must name a link of the URDF, or world");
  if (mount.parent_link == "world") mount.parent_link.clear();
  if (n.has("rpy_deg") && n.has("look_at_m"))
    n.fail("look_at_m", "cannot be given together with rpy_deg");
  mount.T_parent_camera = pose(n);
  if (n.has("look_at_m")) {
    if (!mount.parent_link.empty()) n.fail("look_at_m", "needs parent: world");
    mount.T_parent_camera.linear() = look_at(n, mount.T_parent_camera.translation());
  }
  s.camera_mount = mount;
}

void read_camera(const ConfigNode& n, SceneDescription& s) {
  s.camera_link = n.get<std::string>("link", s.camera_link);
  if (n.has("mount")) read_camera_mount(n.child("mount"), s);
  s.width = int(n.number("width", s.width, 8, 8192));
  s.height = int(n.number("height", s.height, 8, 8192));
  s.fovy_rad = kRadPerDeg * n.number("fovy_deg", s.fovy_rad / kRadPerDeg, 1, 170);
  s.near_m = n.number("near_m", s.near_m, 1e-3, 100);
  s.far_m = n.number("far_m", s.far_m, 1e-2, 1000);
  if (s.far_m <= s.near_m) n.fail("far_m", "must be larger than near_m");
  s.shape_segments = int(n.number("shape_segments", s.shape_segments, 8, 256));
}

ServoGains gains(const ConfigNode& n, const ServoGains& fallback) {
  ServoGains g;
  g.kp_Nm_per_rad = n.number("kp", fallback.kp_Nm_per_rad, 0, 1e6);
  g.kv_Nms_per_rad = n.number("kv", fallback.kv_Nms_per_rad, 0, 1e5);
  return g;
}

void read_actuators(const ConfigNode& n, SceneDescription& s) {
  s.default_gains = gains(n, s.default_gains);
  const ConfigNode joints = n.child("joints");
  for (const std::string& name : joints.keys())
    s.joint_gains[name] = gains(joints.child(name), s.default_gains);
  s.limit_torque_to_urdf_effort =
      n.get<bool>("limit_to_urdf_effort", s.limit_torque_to_urdf_effort);
  s.armature_kg_m2 = n.number("armature_kg_m2", s.armature_kg_m2, 0, 100);
}

void read_physics(const ConfigNode& n, SceneDescription& s) {
  s.timestep_s = n.number("timestep_s", s.timestep_s, 1e-5, 0.1);
  s.gravity_m_s2 = vec<3>(n, "gravity_m_s2", s.gravity_m_s2);
  s.extent_m = n.number("extent_m", s.extent_m, 0.1, 1000);
}

// A table: a top whose upper face is at height_m, centred at position_m
// (x, y), on four legs inset from the corners.
void read_table(const ConfigNode& n, SceneDescription& s) {
  const Eigen::Vector2d xy = vec<2>(n, "position_m", Eigen::Vector2d::Zero());
  const double yaw = kRadPerDeg * n.number("yaw_deg", 0, -360, 360);
  const double height = n.number("height_m", 0.75, 0.05, 3);
  const Eigen::Vector3d top = vec<3>(n, "top_size_m", Eigen::Vector3d(0.8, 1.2, 0.04));
  for (int i = 0; i < 3; ++i)
    if (top[i] <= 0) n.fail("top_size_m", "must hold positive sizes");
  if (top.z() >= height) n.fail("top_size_m", "is thicker than the table is high");
  const Eigen::Vector4f color = rgba(n, Eigen::Vector4f(0.55f, 0.4f, 0.25f, 1.f));
  Eigen::Isometry3d T_world_table = Eigen::Isometry3d::Identity();
  T_world_table.translation() << xy.x(), xy.y(), 0;
  T_world_table.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();

  SceneShape t;
  t.name = "table_top";
  t.size_m = top;
  t.T_world_shape = T_world_table * Eigen::Translation3d(0, 0, height - 0.5 * top.z());
  t.rgba = color;
  s.shapes.push_back(t);
  const double leg = 0.05, leg_height = height - top.z();
  for (int i = 0; i < 4; ++i) {
    SceneShape l;
    l.name = "table_leg_" + std::to_string(i + 1);
    l.size_m << leg, leg, leg_height;
    const double x = (i & 1 ? 1 : -1) * (0.5 * top.x() - leg);
    const double y = (i & 2 ? 1 : -1) * (0.5 * top.y() - leg);
    l.T_world_shape = T_world_table * Eigen::Translation3d(x, y, 0.5 * leg_height);
    l.rgba = color;
    s.shapes.push_back(l);
  }
}

// Shape size from the keys of its type.
Eigen::Vector3d shape_size(const ConfigNode& n, const std::string& type) {
  if (type == "box") {
    const Eigen::Vector3d size = vec<3>(n, "size_m", Eigen::Vector3d::Zero());
    if (!n.has("size_m")) n.fail("size_m", "is required for a box");
    for (int i = 0; i < 3; ++i)
      if (size[i] <= 0) n.fail("size_m", "must hold positive sizes");
    return size;
  }
  if (type == "cylinder") return {length(n, "radius_m"), length(n, "length_m"), 0};
  if (type == "sphere") return {length(n, "radius_m"), 0, 0};
  return {length(n, "height_m"), 0, 0};  // person
}

void read_objects(const ConfigNode& root, SceneDescription& s) {
  for (const ConfigNode& n : root.list("objects")) {
    SceneShape o;
    o.name = n.required<std::string>("name");
    const std::string type = n.choice("type", "box", {"box", "cylinder", "sphere"});
    o.type = type == "box"        ? SceneShape::Type::kBox
             : type == "cylinder" ? SceneShape::Type::kCylinder
                                  : SceneShape::Type::kSphere;
    o.size_m = shape_size(n, type);
    o.T_world_shape = pose(n);
    o.rgba = rgba(n, Eigen::Vector4f(0.2f, 0.5f, 0.8f, 1.f));
    o.free = n.get<bool>("free", false);
    o.mass_kg = n.number("mass_kg", o.mass_kg, 1e-4, 1e3);
    s.shapes.push_back(o);
  }
}

void read_lights(const ConfigNode& root, SceneDescription& s) {
  for (const ConfigNode& n : root.list("lights")) {
    SceneLight l;
    l.position_m = vec<3>(n, "position_m", l.position_m);
    l.direction = vec<3>(n, "direction", l.direction);
    if (l.direction.norm() < 1e-9) n.fail("direction", "must not be zero");
    l.directional = n.get<bool>("directional", false);
    s.lights.push_back(l);
  }
}

void read_occluders(const ConfigNode& root, SceneDescription& s) {
  for (const ConfigNode& n : root.list("occluders")) {
    OccluderSpec o;
    o.name = n.required<std::string>("name");
    const std::string type = n.choice("type", "box", {"box", "cylinder", "person"});
    o.type = type == "box"        ? OccluderSpec::Type::kBox
             : type == "cylinder" ? OccluderSpec::Type::kCylinder
                                  : OccluderSpec::Type::kPerson;
    o.size_m = shape_size(n, type);
    o.T_world_occluder = pose(n);
    o.rgba = rgba(n, o.rgba);
    s.occluders.push_back(o);
  }
}

}  // namespace

SceneDescription load_scene(const fs::path& yaml_path) {
  const YamlDocument doc = load_yaml_file(yaml_path.string());
  const ConfigNode root = ConfigNode::root(doc);
  const fs::path dir = fs::absolute(yaml_path).parent_path();

  SceneDescription s;
  s.source = yaml_path.string();
  if (!root.has("robot")) root.fail("robot", "is required but missing");
  read_robot(root.child("robot"), dir, s);
  read_camera(root.child("camera"), s);
  read_actuators(root.child("actuators"), s);
  read_physics(root.child("physics"), s);
  s.floor = root.get<bool>("floor", true);
  if (root.has("table")) read_table(root.child("table"), s);
  read_objects(root, s);
  read_lights(root, s);
  read_occluders(root, s);
  root.finish();
  return s;
}

fs::path resolve_scene_file(const fs::path& scene_or_scenario) {
  const YamlDocument doc = load_yaml_file(scene_or_scenario.string());
  const ConfigNode root = ConfigNode::root(doc);
  if (!root.has("scene")) return scene_or_scenario;
  const fs::path scene = root.required<std::string>("scene");
  if (scene.is_absolute()) return scene;
  std::error_code ec;
  const fs::path next_to = fs::absolute(scene_or_scenario).parent_path() / scene;
  if (fs::exists(next_to, ec)) return next_to;
  return find_in_search_dirs(scene).value_or(next_to);
}

fs::path default_scene_path() {
  return find_default_file("models/scene_default.yaml", "default scene");
}

}  // namespace arttrack::sim
