// Scene description: which robot, where the depth camera is, what else is in
// the world (floor, table, objects, lights, occluders) and how the physics
// runs. Read once from YAML (load_scene) and checked there; the model builder
// only ever sees this struct.
//
// Frames: poses are in the world frame (z up), which is the frame of the
// robot's URDF root link. Angles are radians here; YAML gives degrees in keys
// ending in `_deg`.
#pragma once

#include <Eigen/Geometry>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arttrack/tracker/units.h"

namespace arttrack::sim {

// A rigid primitive of the scene: part of the table, or an object on it.
struct SceneShape {
  enum class Type { kBox, kCylinder, kSphere };
  std::string name;
  Type type = Type::kBox;
  // Box: full extents x, y, z. Cylinder: radius, length (along z), unused.
  // Sphere: radius, unused, unused. Metres.
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();
  Eigen::Isometry3d T_world_shape = Eigen::Isometry3d::Identity();
  Eigen::Vector4f rgba{0.6f, 0.6f, 0.6f, 1.f};
  // A free body (falls, can be pushed by the arms) instead of a fixed one.
  bool free = false;
  double mass_kg = 0.2;  // used only when free
};

// An occluder: a kinematic (mocap) body that can be moved anywhere, e.g.
// between the camera and an arm. It has no contacts, so it never disturbs the
// robot. A person is a compound of boxes, cylinders and a sphere.
struct OccluderSpec {
  enum class Type { kBox, kCylinder, kPerson };
  std::string name;
  Type type = Type::kBox;
  // Box: full extents. Cylinder: radius, length. Person: height, unused, unused.
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();
  // Initial pose. A person's frame is on the floor between its feet, x
  // forward (the way it faces), z up.
  Eigen::Isometry3d T_world_occluder = Eigen::Isometry3d::Identity();
  Eigen::Vector4f rgba{0.8f, 0.5f, 0.3f, 1.f};
};

// A light (only matters for colour previews, not for depth).
struct SceneLight {
  Eigen::Vector3d position_m{0, 0, 3};
  Eigen::Vector3d direction{0, 0, -1};
  bool directional = false;
};

// Gains of one position servo: torque = kp (target - q) - kv qdot.
struct ServoGains {
  double kp_Nm_per_rad = 200;
  double kv_Nms_per_rad = 20;
};

// A camera the URDF has no link for: a fixed joint named "<camera
// link>_mount" from `parent_link` to a new link (SceneDescription::
// camera_link) at T_parent_camera, added to the simulator's and the tracker's
// copies of the URDF (never to the file).
struct CameraMount {
  std::string parent_link;  // "" : the world (the URDF's root link)
  // The camera's optical frame (z forward, x right, y down) in the parent.
  Eigen::Isometry3d T_parent_camera = Eigen::Isometry3d::Identity();
};

struct SceneDescription {
  // The YAML file the scene came from ("" if built in code); named in errors.
  std::string source;

  // Robot URDF, absolute or relative to the working directory.
  std::filesystem::path urdf_path;
  // Roots for package://NAME/... mesh paths (NAME -> directory). A package not
  // listed is also looked up as a folder of that name next to the URDF, and
  // as the URDF's own folder if NAME is the URDF folder's package.
  std::map<std::string, std::filesystem::path> package_paths;
  // Links whose pose in the camera frame is ground truth (end effectors).
  std::vector<std::string> end_effector_links{"left_ee", "right_ee"};
  // Initial joint angles (URDF joint name -> rad); joints not named start at 0.
  std::map<std::string, double> initial_joints_rad;
  // Named groups of movable joints (`robot.groups`) that scenarios may use
  // in place of joint names; `all` (every movable joint) is always there and
  // is not listed. Checked against the URDF by the scenario.
  std::map<std::string, std::vector<std::string>> joint_groups;
  // Tracker settings that belong to this robot (`robot.tracker_overrides`:
  // dotted tracker key -> value as YAML text), applied over a scenario's
  // tracker file and under the scenario's own tracker_overrides.
  std::vector<std::pair<std::string, std::string>> tracker_overrides;

  // The depth camera sits at this link, which must be an optical frame
  // (z forward, x right, y down): a link of the URDF, or the link the mount
  // adds (then not a link of the URDF).
  std::string camera_link = "camera_optical_frame";
  std::optional<CameraMount> camera_mount;
  int width = 640;
  int height = 480;
  double fovy_rad = 45.0 * kRadPerDeg;  // vertical field of view
  double near_m = 0.1;                  // clipping planes; no return outside
  double far_m = 6.0;
  // Slices of the polygons MuJoCo draws cylinders and spheres with (spheres
  // get half as many stacks). 48 keeps a 10 cm sphere within 2 mm of the
  // true shape; MuJoCo's default 28 is up to 11 mm off. Costs render time.
  int shape_segments = 48;

  // Position servos on every movable robot joint.
  ServoGains default_gains;
  std::map<std::string, ServoGains> joint_gains;  // per-joint overrides
  // Clamp each servo's torque to the URDF joint's effort limit.
  bool limit_torque_to_urdf_effort = true;
  double armature_kg_m2 = 0.01;  // rotor inertia added to every robot joint

  double timestep_s = 0.002;
  Eigen::Vector3d gravity_m_s2{0, 0, -9.81};
  // Size of the world the depth mapping is scaled by; pinned so that adding
  // objects never changes the depth conversion (MuJoCo's stat.extent).
  double extent_m = 4.0;

  bool floor = true;               // a plane at z = 0
  std::vector<SceneShape> shapes;  // table parts and objects
  std::vector<SceneLight> lights;
  std::vector<OccluderSpec> occluders;
};

// Reads a scene YAML file. Paths in it (the URDF, package roots) are relative
// to the file, or to a search folder (search_paths.h) if not found there.
// Unknown keys, wrong types, out-of-range values: InputError naming the file
// and the key.
SceneDescription load_scene(const std::filesystem::path& yaml_path);

// The scene file a YAML file stands for: the file itself if it is a scene,
// or, for a scenario (a top-level `scene:` key naming a scene file, relative
// to the scenario), the scene it names. Missing or malformed file, `scene`
// not a string: InputError naming the file.
std::filesystem::path resolve_scene_file(const std::filesystem::path& scene_or_scenario);

// The default scene: models/scene_default.yaml in the first search folder
// that holds it (search_paths.h); none does: InputError naming the file and
// the folders.
std::filesystem::path default_scene_path();

}  // namespace arttrack::sim
