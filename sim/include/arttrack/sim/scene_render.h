// A scene's depth at one instant, as MuJoCo renders it and as the tracker
// draws the robot: what `arttrack render` writes as PNG files, as images
// (the Python bindings' arttrack.render_scene).
#pragma once

#include <filesystem>
#include <string>

#include "arttrack/tracker/camera.h"

namespace arttrack::sim {

struct SceneRender {
  std::string scene_file;   // the scene YAML that was rendered
  double time_s = 0;        // simulated time of the render
  CameraIntrinsics camera;  // the scene's depth camera
  // Metres along the optical axis, 0 = no return, camera resolution:
  DepthImage scene_depth;  // MuJoCo: the whole scene
  DepthImage robot_depth;  // MuJoCo: the robot alone
  // The tracker's render of the robot at the true state from the true
  // camera, with the geometry it draws (TrackerConfig::geometry of the
  // scenario's tracker configuration, or the default one for a scene).
  DepthImage model_depth;
  int model_triangles = 0;  // of the tracker's model as loaded
  int drawn_triangles = 0;  // of what it draws
};

// Simulates the scene of `scene_or_scenario` (a scene YAML, or a scenario
// naming one) to `time_s` holding the initial (home) pose and renders it.
// Errors: InputError naming the file or the key (as load_scene and
// load_scenario), a time not finite or outside [0, 3600] s.
SceneRender render_scene(const std::filesystem::path& scene_or_scenario, double time_s);

}  // namespace arttrack::sim
