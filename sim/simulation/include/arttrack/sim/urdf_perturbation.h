// Miscalibration and model mismatch of the SIMULATED robot: a rewritten copy
// of the user's URDF whose camera, head kinematics, link lengths or link
// shapes differ from the nominal model the tracker loads.
//
// The user's file is never modified: the copy lives in a private temporary
// folder (PerturbedUrdf), with every mesh file name made absolute so that the
// copy loads from anywhere.
//
// Conventions: URDF joint origins T_parent_joint = Trans(xyz) R(rpy), with
// R(rpy) = Rz(yaw) Ry(pitch) Rx(roll) (URDF's own convention). Lengths in
// metres, angles in radians.
#pragma once

#include <Eigen/Geometry>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "arttrack/sim/motion.h"
#include "arttrack/sim/scene.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack::sim {

// What a URDF declares, read without loading meshes (to check names given in
// scenarios before anything is built).
struct UrdfSummary {
  std::filesystem::path path;
  std::vector<std::string> link_names;   // document order
  std::vector<std::string> joint_names;  // every joint, fixed ones included
  // Joints a servo drives (revolute, continuous, prismatic; not mimic), in
  // document order, and their position limits (infinite if none).
  std::vector<std::string> movable_joints;
  std::vector<JointLimit> movable_limits;
  std::vector<char> movable_prismatic;  // per movable joint: metres, not radians

  bool has_link(const std::string& name) const;
  bool has_joint(const std::string& name) const;
  // Index in movable_joints, or -1.
  int movable_index(const std::string& name) const;
  // Whether `name` is a movable prismatic joint.
  bool is_prismatic(const std::string& name) const;
};

// Reads `urdf`. Missing file, malformed XML, nameless links or joints, past
// a size limit of model_limits.h: InputError naming the file.
UrdfSummary read_urdf_summary(const std::filesystem::path& urdf);

// A change of where one joint sits and which way it turns (a kinematic error
// of, e.g., a robot's neck).
struct JointOriginChange {
  std::string joint;
  // The new origin is the old one followed by this transform (expressed in
  // the joint's nominal frame): T_parent_joint' = T_parent_joint T_old_new.
  Eigen::Isometry3d T_old_new = Eigen::Isometry3d::Identity();
  // Rotation applied to the joint's axis direction, in the new joint frame:
  // axis' = R_axis axis (a tilt of the axis).
  Eigen::Matrix3d R_axis = Eigen::Matrix3d::Identity();
};

// Everything that makes the simulated robot differ from the nominal one.
// Applied in this order: camera mount, origin extensions, joint origin changes, camera
// offset; shape scales act on geometry only.
struct UrdfPerturbation {
  // Link of the camera's optical frame; its parent joint's origin moves.
  std::string camera_link = "camera_optical_frame";
  // The TRUE camera frame in the nominal camera frame:
  // T_root_true = T_root_nominal T_nominal_true (identity: no offset).
  Eigen::Isometry3d T_nominal_true_camera = Eigen::Isometry3d::Identity();
  // Changes of joint origins and axes (the head's kinematic error).
  std::vector<JointOriginChange> joint_changes;
  // Link length changes, m, by joint: the joint's origin moves by this much
  // along its own translation (the parent link grows by it; negative
  // shrinks). A joint whose origin has no translation cannot take one.
  std::map<std::string, double> origin_extension_m;
  // Uniform scale (> 0) of all visual and collision geometry of a link about
  // the link frame, by link name (shape mismatch).
  std::map<std::string, double> link_scale;
  // Not a difference: the scene's camera mount (scene.h), which the nominal
  // robot has too. Adds camera_link before everything else; empty() ignores it.
  std::optional<CameraMount> camera_mount;

  bool empty() const;
};

// Rewrites URDF text. Mesh file names are resolved (package:// through
// `package_paths`, else as the scene builder does; relative ones against
// `urdf_dir`) and made absolute. An unknown joint or link, an origin
// extension of a joint without translation, a camera link without a parent
// joint, a non-positive or non-finite value, malformed XML or an
// unresolvable mesh package: InputError naming `source` and the item.
std::string perturb_urdf_text(const std::string& xml, const std::string& source,
                              const std::filesystem::path& urdf_dir,
                              const std::map<std::string, std::filesystem::path>& package_paths,
                              const UrdfPerturbation& perturbation);

// The text of `urdf` with `changes` and the scene's camera link and mount
// (if any) applied and mesh file names made absolute. Errors as
// perturb_urdf_text, plus a missing or unreadable file.
std::string perturbed_urdf_text(const SceneDescription& scene, const std::filesystem::path& urdf,
                                UrdfPerturbation changes);
// perturbed_urdf_text without changes: the nominal robot as the tracker
// loads it.
std::string mounted_urdf_text(const SceneDescription& scene, const std::filesystem::path& urdf);

// The tracker's model of `urdf` in `scene`: mounted_urdf_text loaded with
// `options`, whose camera frame is set to the scene's camera link and whose
// mesh search paths get the scene's package folders.
RobotModel tracker_robot_model(const SceneDescription& scene, const std::filesystem::path& urdf,
                               RobotModelOptions options = {});

// A perturbed copy of a URDF file in a private temporary folder that is
// removed with this object. Keep it alive until the simulator's model is
// built from path().
class PerturbedUrdf {
 public:
  // Errors as perturb_urdf_text, plus a missing or unreadable file.
  PerturbedUrdf(const std::filesystem::path& urdf,
                const std::map<std::string, std::filesystem::path>& package_paths,
                const UrdfPerturbation& perturbation);
  ~PerturbedUrdf();
  PerturbedUrdf(const PerturbedUrdf&) = delete;
  PerturbedUrdf& operator=(const PerturbedUrdf&) = delete;

  // The perturbed URDF file.
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path dir_, path_;
};

}  // namespace arttrack::sim
