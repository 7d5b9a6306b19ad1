// A scenario: one experiment of the testbed, read from YAML and checked
// there (scenarios/README.md documents every key). It says which scene, how
// the robot moves, what loads it lifts, how its encoders and depth camera
// lie, how the simulated robot differs from the nominal model the tracker
// knows, what occludes the view, which tracking methods run and how they are
// scored.
//
// Units: SI, angles in radians in the structs (YAML gives degrees in keys
// ending in `_deg`). Poses are in the world frame (the URDF root link's).
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "arttrack/sim/depth_corruption.h"
#include "arttrack/sim/encoder_corruption.h"
#include "arttrack/sim/motion.h"
#include "arttrack/sim/scene.h"
#include "arttrack/sim/scoring.h"
#include "arttrack/sim/urdf_perturbation.h"
#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/tracker_config.h"
#include "arttrack/tracker/yaml_config.h"

namespace arttrack::sim {

// One pose of an occluder's schedule.
struct OccluderKeyframe {
  double time_s = 0;
  Eigen::Isometry3d T_world_occluder = Eigen::Isometry3d::Identity();
};

// An occluder moving on a schedule: its pose is interpolated linearly
// between keyframes (position linearly, rotation by slerp) and held before
// the first and after the last.
struct OccluderSchedule {
  // Index into the scene's occluders (SceneDescription::occluders).
  int occluder = -1;
  // At least one keyframe, times strictly increasing.
  std::vector<OccluderKeyframe> keyframes;

  // The occluder's pose at time t_s.
  Eigen::Isometry3d pose_at(double t_s) const;
};

// Lifting a load: a downward force m g (the scene's gravity) at the origin of
// a link's frame (MuJoCo xfrc_applied on the link's body), ramped in and out
// with a cosine ramp. The joints' torques change, and cable stretch with them.
struct LinkLoad {
  std::string link;
  double mass_kg = 1.0;  // > 0
  double start_s = 0;    // the force starts to ramp in
  double end_s = 0;      // the force has ramped out (>= start_s + 2 ramp_s)
  double ramp_s = 0.5;   // duration of each ramp, >= 0

  // Fraction of the full force at time t_s, in [0, 1].
  double weight(double t_s) const;
};

// How the methods are scored.
struct ScenarioScoring {
  ScoringOptions options;
  // Also score every N joint steps (0: only at camera frames).
  int every_n_joint_steps = 0;
  // End effectors scored (links of the URDF), each with its own statistics
  // and a pooled worst (scoring.h).
  std::vector<std::string> end_effectors;
};

// Model error drawn per run (model_mismatch.random): `lengths` of the
// `joints` have their origin moved along its own translation by a length
// drawn uniformly in [length_min_m, length_max_m], longer or shorter at
// even odds; `scales` of the `links` are scaled by 1 +- a value drawn
// uniformly in [scale_min, scale_max]. Which ones, how much and which sign
// are drawn anew for every run, so the runs of a file are a population of
// robots within one error budget rather than one robot.
struct RandomModelMismatch {
  std::vector<std::string> joints;  // joints whose origins may be off
  int lengths = 0;                  // how many of them are, per run
  double length_min_m = 0, length_max_m = 0;
  std::vector<std::string> links;  // links whose shapes may be scaled
  int scales = 0;                  // how many of them are, per run
  double scale_min = 0, scale_max = 0;

  bool empty() const { return lengths == 0 && scales == 0; }
};

struct Scenario {
  // Name (the `name` key, else the file's stem), used for output folders.
  std::string name;
  // The scenario file, named in messages.
  std::string source;
  // What reproduces it (summary.json "reproduce", arttrack rerun): the folder
  // its relative paths resolve against, the overrides applied in order, the
  // document after `extends` and overrides (YAML, `name` included); the
  // tracker configuration's is tracker_document.
  std::filesystem::path dir;
  std::vector<std::string> overrides;
  std::string resolved_yaml;

  // The scene, with the scenario's camera settings, end effectors and
  // occluders applied. Its URDF is the NOMINAL one (the tracker's); the
  // simulator uses it with `perturbation` applied.
  std::filesystem::path scene_file;
  SceneDescription scene;
  UrdfSummary urdf;
  // The URDFs the simulator and the tracker load (`simulated_urdf`,
  // `tracker_urdf`; empty: the scene's): e.g. a calibrated description
  // simulated and the nominal one tracked. Same movable joints as `urdf`.
  std::filesystem::path simulated_urdf_path, tracker_urdf_path;
  const std::filesystem::path& simulated_urdf() const {
    return simulated_urdf_path.empty() ? scene.urdf_path : simulated_urdf_path;
  }
  const std::filesystem::path& tracker_urdf() const {
    return tracker_urdf_path.empty() ? scene.urdf_path : tracker_urdf_path;
  }

  // Tracker configuration (its method is set per run for each method), the
  // file it came from (empty: the built-in default, kDefaultTrackerConfigName)
  // and its document with the scene's and the scenario's tracker_overrides
  // applied (what `tracker` was read from).
  std::filesystem::path tracker_file;
  YamlDocument tracker_document;
  TrackerConfig tracker;
  // The scenario's own tracker_overrides (the key as --set writes it, the
  // value as one line of YAML), in file order: applied over the scene's.
  std::vector<std::pair<std::string, std::string>> tracker_overrides;
  // Methods to run, as named by all_method_names().
  std::vector<std::string> methods;

  double duration_s = 10.0;       // simulated time, > 0
  std::uint64_t seed = 1;         // seed of run 0; runs derive theirs from it
  int runs = 1;                   // K runs with different seeds
  double joint_rate_hz = 1000.0;  // encoder rate

  // Commanded motion, joints named in full (groups expanded).
  std::vector<SinusoidMotion> sinusoids;
  std::vector<WaypointMotion> waypoints;
  std::vector<RandomMotion> random;
  std::vector<OutOfViewMotion> out_of_view;
  std::vector<LinkLoad> loads;

  // Encoder corruption; a file's group that names revolute and prismatic
  // joints is two groups here (degree keys for the one, metre keys for the
  // other), with the joints named in full.
  EncoderCorruptionParams encoders;
  CameraTiming camera_timing;
  DepthCorruptionParams depth_corruption;
  // camera.focal_error: the focal lengths the camera reports are (1 +
  // focal_error) times those it renders with, a calibration error
  // (reported_intrinsics).
  double focal_error = 0;
  // Differences of the simulated robot from the nominal URDF.
  UrdfPerturbation perturbation;
  // Model error drawn afresh for each run (model_mismatch.random), on top of
  // `perturbation`: every run simulates another robot of the same budget.
  RandomModelMismatch random_mismatch;
  // Moving occluders (scene occluders without a schedule stay put).
  std::vector<OccluderSchedule> occluder_schedules;

  ScenarioScoring scoring;
};

// A robot's model error drawn from the run's seed (model_mismatch.random):
// run_model_error gives the perturbation the run simulates and what was
// drawn.
struct DrawnModelError {
  UrdfPerturbation perturbation;                 // the scenario's, plus the draws
  std::map<std::string, double> link_lengths_m;  // drawn origin changes, by joint
  std::map<std::string, double> shape_scales;    // drawn scales, by link
};
// `seed` is the run's model stream. Without model_mismatch.random: the
// scenario's perturbation and nothing drawn.
DrawnModelError run_model_error(const Scenario& scenario, std::uint64_t seed);

// The intrinsics the scenario's camera reports, which the trackers and an
// exported dataset get: `rendered` (the simulated camera's) with focal
// lengths (1 + focal_error) times its own.
CameraIntrinsics reported_intrinsics(const Scenario& scenario, const CameraIntrinsics& rendered);

// Loads a scenario file (following `extends:`), applies the overrides
// ("dotted.key=value", as arttrack run --set) and parses it. Relative paths
// (scene, tracker) are relative to the scenario file, else to a search
// folder (search_paths.h). Unknown keys, wrong types, impossible values,
// unknown joints, groups, links or methods: InputError naming the file and
// the key path.
Scenario load_scenario(const std::filesystem::path& path,
                       const std::vector<std::string>& overrides = {});

// The same from a loaded document; relative paths resolve against `dir`.
// `tracker` (a resolved tracker configuration, Scenario::tracker_document) replaces
// the `tracker` file and tracker_overrides when given.
Scenario scenario_from_yaml(const YamlDocument& doc, const std::filesystem::path& dir,
                            const YamlDocument* tracker = nullptr);

// Gives `scenario` another tracker configuration, as if its `tracker` key
// named `file` holding `document` (e.g. a tuning candidate, built in
// memory): the scene's robot.tracker_overrides and the scenario's own
// tracker_overrides are applied over a copy of `document`, which is then read
// and validated (TrackerConfig::validate); the camera frame and the end
// effectors are the scenario's. Sets tracker_file, tracker_document and
// tracker. InputError as load_scenario's, naming the override that set a
// bad key.
void set_tracker_document(Scenario& scenario, const YamlDocument& document,
                          const std::filesystem::path& file);

// The joints a name stands for on a robot: `all` (every one of `joints`), a
// group of the scene (`groups`: SceneDescription::joint_groups), else the
// joint itself. Returns no joints for a name that is neither a group nor
// one of `joints`.
std::vector<std::string> expand_joint_group(
    const std::string& name, const std::vector<std::string>& joints,
    const std::map<std::string, std::vector<std::string>>& groups);

// The commanded trajectory of a scenario for the simulator's joints
// (`joint_names`, their limits and home configuration, clamped into the
// limits); random motion draws from `rng`.
JointTrajectory make_trajectory(const Scenario& scenario,
                                const std::vector<std::string>& joint_names,
                                const std::vector<JointLimit>& limits,
                                const std::vector<double>& home_rad, std::mt19937_64& rng);

// Reads the scoring options of a `scoring` map (scenarios and dataset.yaml):
// converged_after_s, convergence_threshold_m, lost_threshold_m,
// lost_after_s; absent keys keep `options`' values. Wrong types and values
// out of range: InputError naming the file and the key.
void read_scoring_options(const ConfigNode& scoring, ScoringOptions& options);

// The default scenario: scenarios/default.yaml in the first search folder
// that holds it (search_paths.h); none does: InputError naming the file and
// the folders.
std::filesystem::path default_scenario_path();

}  // namespace arttrack::sim
