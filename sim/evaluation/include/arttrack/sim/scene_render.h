// A scene's depth at one instant, as MuJoCo renders it and as the tracker
// draws the robot: what `arttrack render` writes as PNG files, as images
// (the Python bindings' arttrack.render_scene).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "arttrack/tracker/camera.h"

namespace arttrack::sim {

struct SceneRender {
  std::string scene_file;      // the scene YAML that was rendered
  std::string robot_urdf;      // the tracker's robot description
  std::string simulated_urdf;  // the simulated robot's (a scenario's simulated_urdf)
  // How the simulated robot differs from robot_urdf (a scenario's
  // model_mismatch, head error and miscalibration), for people; "none".
  std::string model_mismatch;
  double time_s = 0;  // simulated time of the render
  // The simulated robot's joints and their true angles then (rad; m for
  // prismatic joints), in the simulator's order.
  std::vector<std::string> joint_names;
  std::vector<double> joint_angle_rad;
  CameraIntrinsics camera;        // the scene's depth camera
  std::string gl;                 // the OpenGL renderer MuJoCo used
  bool follows_scenario = false;  // the robot followed a scenario's motion (else: home)
  double near_m = 0, far_m = 0;   // the scene's depth range
  // Metres along the optical axis, 0 = no return, camera resolution:
  DepthImage scene_depth;  // MuJoCo: the whole scene
  DepthImage robot_depth;  // MuJoCo: the robot alone
  // The tracker's render of its model at the true angles from the true
  // camera, with the geometry it draws (TrackerConfig::geometry of the
  // scenario's tracker configuration, or the default one for a scene):
  // where it differs from robot_depth, it is the model error.
  DepthImage model_depth;
  DepthImage full_model_depth;  // the same with the full meshes
  std::string mesh_parts;       // describe_mesh_parts() of the tracker's model
  int model_triangles = 0;      // of the tracker's model as loaded
  int drawn_triangles = 0;      // of what it draws
  // Per coarser level k = 1, 2, ...: triangles drawn beyond nearest_range_m 2^k.
  std::vector<int> level_triangles;
  CameraIntrinsics likelihood_camera;            // the resolution the geometry is simplified for
  double max_error_px = 0, nearest_range_m = 0;  // TrackerConfig::geometry
  double error_bound_m = 0;                      // the simplification's bound
  double simplifier_error_m = 0;                 // what the simplifier reports
};

// Simulates the scene of `scene_or_scenario` (a scene YAML, or a scenario
// naming one) to `time_s` and renders it. A scene holds the initial (home)
// pose; a scenario's is its first run's (seed: the scenario's when
// negative) at the joint step nearest `time_s`, as `arttrack run` simulates
// it (run_physics.h: its motion, loads and occluders), on the robot that run
// simulates (its simulated_urdf and model_mismatch, under
// model_mismatch.random run 0's draw, its head error and camera
// miscalibration). Errors: InputError naming the file or the key (as
// load_scene and load_scenario), a time not finite or outside [0, 3600] s.
SceneRender render_scene(const std::filesystem::path& scene_or_scenario, double time_s,
                         std::int64_t seed = -1);

}  // namespace arttrack::sim
