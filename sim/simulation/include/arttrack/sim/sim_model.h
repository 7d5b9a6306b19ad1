// The MuJoCo model of a scene: robot (from its URDF), depth camera, floor,
// table, objects, lights, occluders, position servos and physics options.
// Built once from a SceneDescription and immutable afterwards; share it
// between simulators and renderers as std::shared_ptr<const SimModel>.
//
// How it is built (MuJoCo 2.2): the URDF is rewritten in a temporary folder
// (meshes converted to uniquely named binary STL, a compiler block that keeps
// visual geometry and fixed links), loaded, saved as MJCF, and the MJCF is
// extended with the scene. Robot body frames are the URDF link frames.
//
// Geom groups (for rendering subsets): robot collision 0, robot visual 1,
// floor/table/objects 2, occluders 3. Contacts: robot against the scene only
// (never against itself, so it cannot jam), scene against scene; occluders
// have no contacts.
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

#include "arttrack/sim/scene.h"
#include "arttrack/sim/urdf_perturbation.h"
#include "arttrack/tracker/camera.h"

namespace arttrack::sim {

constexpr int kGroupRobotCollision = 0;
constexpr int kGroupRobotVisual = 1;
constexpr int kGroupScene = 2;
constexpr int kGroupOccluder = 3;

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};

struct SimModel {
  SceneDescription scene;
  std::unique_ptr<mjModel, MjModelDeleter> mj;
  // The MJCF the model was compiled from (meshes named by file only), for
  // inspection.
  std::string mjcf;

  // Robot joints with a servo (URDF revolute, continuous, prismatic, not
  // mimic), in URDF document order. Vectors of joint values use this order.
  std::vector<std::string> joint_names;
  std::vector<int> joint_id;        // MuJoCo joint id
  std::vector<int> joint_qpos_adr;  // address in qpos
  std::vector<int> joint_dof_adr;   // address in qvel / qfrc_*
  std::vector<int> joint_actuator;  // the joint's servo (ctrl index)
  Eigen::VectorXd joint_lower;      // limits, rad or m (-inf/+inf if none)
  Eigen::VectorXd joint_upper;
  Eigen::VectorXd initial_joints;  // from the scene, rad or m

  // URDF links in document order, and their MuJoCo bodies.
  std::vector<std::string> link_names;
  std::vector<int> link_body;
  std::string root_link;

  int camera_id = -1;    // MuJoCo camera at the camera link
  int camera_body = -1;  // body of the camera link (the optical frame)
  // A robot visual mesh has an open part (orient_parts()): the depth camera
  // draws both sides of every surface (MuJoCo culls back faces otherwise).
  bool render_both_sides = false;
  std::vector<std::string> end_effector_names;
  std::vector<int> end_effector_body;
  std::vector<std::string> occluder_names;
  std::vector<int> occluder_mocap;  // index into mocap_pos / mocap_quat

  // -1 if there is no such joint, link or occluder.
  int joint_index(const std::string& name) const;
  int link_index(const std::string& name) const;
  int occluder_index(const std::string& name) const;

  // The depth camera's intrinsics at the scene's resolution.
  CameraIntrinsics intrinsics() const;
};

// Builds the MuJoCo model of `scene`, its robot changed by `perturbation`
// (a scenario's miscalibration and model mismatch; the scene's camera mount
// is added either way). Every description the tracker loads (urdfdom) also
// loads here: what MuJoCo 2.2 refuses and urdfdom tolerates is normalised
// (urdf_prepare.h). Any problem (missing URDF or mesh, past a size limit of
// model_limits.h, unknown camera link, joint or end effector, what MuJoCo
// 2.2 cannot simulate): InputError naming the user's file, the item and,
// for an element of the URDF, its line there; never a temporary copy.
std::shared_ptr<const SimModel> build_sim_model(const SceneDescription& scene,
                                                const UrdfPerturbation& perturbation = {});

}  // namespace arttrack::sim
