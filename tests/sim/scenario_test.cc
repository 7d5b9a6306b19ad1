// Scenario YAML: defaults, every key read into the struct (degrees to
// radians, groups expanded, sweeps turned into keyframes), extends and
// overrides, and bad input (unknown key, wrong type, impossible value,
// unknown joint, group, link or method) an InputError naming the file and
// the key path. Every scenario shipped in scenarios/ loads.
#include "arttrack/sim/scenario.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/units.h"
#include "scenario_test_robot.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;

// Expects load_scenario to throw an InputError whose message holds every
// one of `parts`.
void expect_error(const fs::path& file, const std::vector<std::string>& parts,
                  const std::vector<std::string>& overrides = {}) {
  try {
    load_scenario(file, overrides);
    FAIL() << "no error for " << file;
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const std::string& p : parts)
      EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' missing from: " << what;
  }
}

TEST(Scenario, Defaults) {
  const test::TestDir dir("scenario_defaults");
  const Scenario s = load_scenario(dir.write("minimal.yaml", "scene: scene.yaml\n"));
  EXPECT_EQ(s.name, "minimal");
  EXPECT_EQ(s.duration_s, 10.0);
  EXPECT_EQ(s.seed, 1u);
  EXPECT_EQ(s.runs, 1);
  EXPECT_EQ(s.joint_rate_hz, 1000.0);
  EXPECT_EQ(s.methods, all_method_names());
  EXPECT_TRUE(s.tracker_file.empty());  // the built-in default
  EXPECT_EQ(s.tracker.source, kDefaultTrackerConfigName);
  EXPECT_EQ(s.tracker.method, TrackingMethod::kFullFusion);
  EXPECT_EQ(s.tracker.end_effectors, (std::vector<std::string>{"left_ee", "right_ee"}));
  EXPECT_EQ(s.scene.width, 160);  // the scene's camera
  EXPECT_EQ(s.camera_timing.rate_hz, 30.0);
  EXPECT_EQ(s.camera_timing.latency_s, 0.0);
  EXPECT_EQ(s.depth_corruption.noise_sigma0_m, 0.0);
  EXPECT_TRUE(s.perturbation.empty());
  EXPECT_TRUE(s.encoders.groups.empty());
  EXPECT_TRUE(s.sinusoids.empty() && s.waypoints.empty() && s.random.empty() &&
              s.out_of_view.empty() && s.loads.empty() && s.occluder_schedules.empty());
  EXPECT_EQ(s.scoring.end_effectors, (std::vector<std::string>{"left_ee", "right_ee"}));
  EXPECT_EQ(s.scoring.options.converged_after_s, 10.0);
  EXPECT_EQ(s.scoring.options.lost_threshold_m, 0.02);
  EXPECT_EQ(s.scoring.options.lost_after_s, 1.0);
  EXPECT_EQ(s.scoring.every_n_joint_steps, 0);
  EXPECT_EQ(s.urdf.movable_joints.size(), 6u);
}

constexpr char kFull[] = R"(
name: everything
scene: scene.yaml
duration_s: 12.5
seed: 42
runs: 3
joint_rate_hz: 500
methods: [full_fusion, encoders_only]
tracker_overrides: {particle_filter.particles: 7, depth_model.width: 40, depth_model.height: 30}
motion:
  sinusoids:
    - {joints: [left_arm], amplitude_deg: 10, frequency_hz: 0.5, phase_deg: 90, fade_in_s: 1}
  waypoints:
    - {joints: [head_pan_joint], times_s: [0, 2], positions_deg: [[0], [30]]}
  random:
    - {joints: [right_arm_joint_1], amplitude_deg: 20, speed_scale: 3, base_speed_deg_per_s: 10,
       margin_deg: 2, components: 5, fade_in_s: 0.5}
  out_of_view:
    - {joints: [right_arm_joint_2], out_of_view_deg: [80], leave_s: 3, return_s: 8, move_duration_s: 1}
loads:
  - {link: left_ee, mass_kg: 2, start_s: 1, end_s: 5, ramp_s: 0.5}
encoders:
  - {joints: [arms], offset_deg: 8.6, noise_deg: 0.01}
  - {joints: [head], step_amplitude_deg: 5, step_period_s: 10, step_ramp_time_s: 2,
     compliance_deg_per_Nm: 0.2, stretch_time_constant_s: 0.1, resolution_deg: 0.02}
camera:
  width: 320
  height: 240
  fovy_deg: 60
  rate_hz: 15
  latency_s: 0.05
  jitter_s: 0.01
  jitter: uniform
  drop_probability: 0.1
  noise_sigma0_m: 0.001
  noise_quadratic_per_m: 0.002
  baseline_focal_m_px: 43.5
  dropout_probability: 0.02
  edge_dropout_probability: 0.5
  max_range_m: 4
  depth_scale_error: -0.004
  focal_error: 0.01
miscalibration:
  camera_offset: {xyz_m: [0.01, -0.02, 0.03], rpy_deg: [1, 2, 3]}
  head_error:
    head_tilt_joint: {xyz_m: [0, 0, 0.005], rpy_deg: [0, 1, 0], axis_tilt_deg: [2, 0, 0]}
model_mismatch:
  link_lengths_m: {left_arm_joint_2: 0.01}
  shape_scale: {left_arm_fore: 1.1}
occluders:
  - name: board
    type: box
    size_m: [0.5, 0.02, 0.5]
    keyframes:
      - {time_s: 1, position_m: [0.3, 0, 1.2]}
      - {time_s: 3, position_m: [0.3, 0.4, 1.2], rpy_deg: [0, 0, 90]}
  - name: walker
    type: person
    height_m: 1.7
    sweep: {from: {position_m: [1, -1, 0]}, to: {position_m: [1, 1, 0]}, start_s: 2,
            duration_s: 4, passes: 2, pause_s: 1}
scoring:
  converged_after_s: 6
  convergence_threshold_m: 0.005
  lost_threshold_m: 0.05
  lost_after_s: 2.5
  every_n_joint_steps: 10
  end_effectors: [left_ee]
)";

TEST(Scenario, EveryKeyIsRead) {
  const test::TestDir dir("scenario_every_key");
  const Scenario s = load_scenario(dir.write("full.yaml", kFull));
  EXPECT_EQ(s.name, "everything");
  EXPECT_EQ(s.duration_s, 12.5);
  EXPECT_EQ(s.seed, 42u);
  EXPECT_EQ(s.runs, 3);
  EXPECT_EQ(s.joint_rate_hz, 500.0);
  EXPECT_EQ(s.methods, (std::vector<std::string>{"full_fusion", "encoders_only"}));
  EXPECT_EQ(s.tracker.particle_filter.num_particles, 7);
  EXPECT_EQ(s.tracker.depth_model.width, 40);

  ASSERT_EQ(s.sinusoids.size(), 1u);
  EXPECT_EQ(s.sinusoids[0].joints,
            (std::vector<std::string>{"left_arm_joint_1", "left_arm_joint_2"}));
  EXPECT_DOUBLE_EQ(s.sinusoids[0].amplitude_rad, 10 * kRadPerDeg);
  EXPECT_DOUBLE_EQ(s.sinusoids[0].phase_rad, 90 * kRadPerDeg);
  ASSERT_EQ(s.waypoints.size(), 1u);
  EXPECT_DOUBLE_EQ(s.waypoints[0].positions_rad[1][0], 30 * kRadPerDeg);
  ASSERT_EQ(s.random.size(), 1u);
  EXPECT_EQ(s.random[0].num_components, 5);
  EXPECT_DOUBLE_EQ(s.random[0].base_speed_rad_per_s, 10 * kRadPerDeg);
  EXPECT_DOUBLE_EQ(s.random[0].margin_rad, 2 * kRadPerDeg);
  ASSERT_EQ(s.out_of_view.size(), 1u);
  EXPECT_DOUBLE_EQ(s.out_of_view[0].out_of_view_rad[0], 80 * kRadPerDeg);
  EXPECT_EQ(s.out_of_view[0].return_s, 8.0);

  ASSERT_EQ(s.loads.size(), 1u);
  EXPECT_EQ(s.loads[0].link, "left_ee");
  EXPECT_EQ(s.loads[0].mass_kg, 2.0);

  ASSERT_EQ(s.encoders.groups.size(), 2u);
  EXPECT_EQ(s.encoders.groups[0].joints.size(), 4u);
  EXPECT_DOUBLE_EQ(s.encoders.groups[0].offset_rad, 8.6 * kRadPerDeg);
  EXPECT_DOUBLE_EQ(s.encoders.groups[0].noise_sigma_rad, 0.01 * kRadPerDeg);
  EXPECT_EQ(s.encoders.groups[1].joints,
            (std::vector<std::string>{"head_pan_joint", "head_tilt_joint"}));
  EXPECT_DOUBLE_EQ(s.encoders.groups[1].step_amplitude_rad, 5 * kRadPerDeg);
  EXPECT_DOUBLE_EQ(s.encoders.groups[1].compliance_rad_per_Nm, 0.2 * kRadPerDeg);
  EXPECT_DOUBLE_EQ(s.encoders.groups[1].resolution_rad, 0.02 * kRadPerDeg);

  EXPECT_EQ(s.scene.width, 320);
  EXPECT_EQ(s.scene.height, 240);
  EXPECT_DOUBLE_EQ(s.scene.fovy_rad, 60 * kRadPerDeg);
  EXPECT_EQ(s.camera_timing.rate_hz, 15.0);
  EXPECT_EQ(s.camera_timing.jitter, CameraTiming::Jitter::kUniform);
  EXPECT_EQ(s.camera_timing.drop_probability, 0.1);
  EXPECT_EQ(s.depth_corruption.baseline_focal_m_px, 43.5);
  EXPECT_EQ(s.depth_corruption.max_range_m, 4.0);
  EXPECT_EQ(s.depth_corruption.depth_scale_error, -0.004);
  EXPECT_EQ(s.focal_error, 0.01);
  const CameraIntrinsics rendered = CameraIntrinsics::from_vertical_fov(320, 240, s.scene.fovy_rad);
  const CameraIntrinsics reported = reported_intrinsics(s, rendered);
  EXPECT_DOUBLE_EQ(reported.fx, 1.01 * rendered.fx);
  EXPECT_DOUBLE_EQ(reported.fy, 1.01 * rendered.fy);
  EXPECT_EQ(reported.cx, rendered.cx);
  EXPECT_EQ(reported.width, rendered.width);

  const Eigen::Isometry3d& T = s.perturbation.T_nominal_true_camera;
  EXPECT_LT((T.translation() - Eigen::Vector3d(0.01, -0.02, 0.03)).norm(), 1e-15);
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(3 * kRadPerDeg, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(2 * kRadPerDeg, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(1 * kRadPerDeg, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  EXPECT_LT((T.linear() - R).norm(), 1e-15);
  ASSERT_EQ(s.perturbation.joint_changes.size(), 1u);
  EXPECT_EQ(s.perturbation.joint_changes[0].joint, "head_tilt_joint");
  EXPECT_DOUBLE_EQ(s.perturbation.joint_changes[0].T_old_new.translation().z(), 0.005);
  EXPECT_EQ(s.perturbation.origin_extension_m.at("left_arm_joint_2"), 0.01);
  EXPECT_EQ(s.perturbation.link_scale.at("left_arm_fore"), 1.1);

  // Two new occluders; the sweep becomes keyframes out, pause, back.
  ASSERT_EQ(s.scene.occluders.size(), 2u);
  EXPECT_EQ(s.scene.occluders[1].type, OccluderSpec::Type::kPerson);
  EXPECT_EQ(s.scene.occluders[1].size_m.x(), 1.7);
  ASSERT_EQ(s.occluder_schedules.size(), 2u);
  const OccluderSchedule& walk = s.occluder_schedules[1];
  ASSERT_EQ(walk.keyframes.size(), 4u);
  EXPECT_EQ(walk.keyframes[1].time_s, 6.0);
  EXPECT_EQ(walk.keyframes[2].time_s, 7.0);
  EXPECT_EQ(walk.keyframes[3].time_s, 11.0);
  EXPECT_EQ(walk.keyframes[3].T_world_occluder.translation().y(), -1.0);
  EXPECT_EQ(walk.pose_at(4.0).translation().y(), 0.0);  // halfway out
  EXPECT_EQ(walk.pose_at(6.5).translation().y(), 1.0);  // pausing
  // The initial pose is the first keyframe's.
  EXPECT_EQ(s.scene.occluders[0].T_world_occluder.translation().y(), 0.0);

  EXPECT_EQ(s.scoring.options.converged_after_s, 6.0);
  EXPECT_EQ(s.scoring.options.convergence_threshold_m, 0.005);
  EXPECT_EQ(s.scoring.options.lost_threshold_m, 0.05);
  EXPECT_EQ(s.scoring.options.lost_after_s, 2.5);
  EXPECT_EQ(s.scoring.every_n_joint_steps, 10);
  EXPECT_EQ(s.scoring.end_effectors, (std::vector<std::string>{"left_ee"}));
  EXPECT_EQ(s.tracker.end_effectors, (std::vector<std::string>{"left_ee"}));
}

TEST(Scenario, ExtendsAndOverrides) {
  const test::TestDir dir("scenario_extends");
  dir.write("base.yaml", R"(
name: base
scene: scene.yaml
duration_s: 5
seed: 3
encoders: [{joints: [arms], offset_deg: 8.6}]
camera: {rate_hz: 20, latency_s: 0.1}
)");
  const fs::path child = dir.write("child.yaml", R"(
extends: base.yaml
seed: 7
camera: {latency_s: 0.02}
)");
  const Scenario s = load_scenario(child);
  EXPECT_EQ(s.name, "child");                // the base's name is not inherited
  EXPECT_EQ(s.duration_s, 5.0);              // from the base
  EXPECT_EQ(s.seed, 7u);                     // the extending file wins
  EXPECT_EQ(s.camera_timing.rate_hz, 20.0);  // maps merge deeply
  EXPECT_EQ(s.camera_timing.latency_s, 0.02);
  ASSERT_EQ(s.encoders.groups.size(), 1u);

  const Scenario o =
      load_scenario(child, {"duration_s=2", "camera.rate_hz=10", "methods=[encoders_only]",
                            "encoders=[{joints: [left_arm], offset_deg: 1}]"});
  EXPECT_EQ(o.duration_s, 2.0);
  EXPECT_EQ(o.camera_timing.rate_hz, 10.0);
  EXPECT_EQ(o.methods, (std::vector<std::string>{"encoders_only"}));
  ASSERT_EQ(o.encoders.groups.size(), 1u);
  EXPECT_EQ(o.encoders.groups[0].joints.size(), 2u);
  EXPECT_DOUBLE_EQ(o.encoders.groups[0].offset_rad, kRadPerDeg);

  expect_error(child, {"override", "novalue"}, {"novalue"});

  // A file's own tracker_overrides survive an override that adds to them,
  // written as a path or as a map, and reach the tracker merged into its
  // `uncertainty` map, not in place of it (until stop 85 the second form
  // dropped the file's depth_scale_std).
  const fs::path told = dir.write("told.yaml", R"(
extends: base.yaml
tracker_overrides: {uncertainty.depth_scale_std: 0.005}
)");
  for (const std::string& set :
       {std::string("tracker_overrides.uncertainty.model_error_unpinned_scale=4"),
        std::string("tracker_overrides={uncertainty: {model_error_unpinned_scale: 4}}")}) {
    const Scenario t = load_scenario(told, {set});
    EXPECT_EQ(t.tracker.depth_scale_std, 0.005) << set;
    EXPECT_EQ(t.tracker.model_error_unpinned_scale, 4.0) << set;
  }
  EXPECT_EQ(load_scenario(told, {"tracker_overrides={}"}).tracker.depth_scale_std, 0.0);
}

TEST(Scenario, UnknownKeysAreNamedWithPathAndFile) {
  const test::TestDir dir("scenario_unknown_keys");
  const fs::path top = dir.write("top.yaml", "scene: scene.yaml\nduraton_s: 3\n");
  expect_error(top, {top.string(), "'duraton_s'", "not a known key"});
  const fs::path nested =
      dir.write("nested.yaml", "scene: scene.yaml\nencoders: [{joints: [arms], offset: 5}]\n");
  expect_error(nested, {nested.string(), "'encoders[0].offset'"});
  const fs::path deep = dir.write(
      "deep.yaml", "scene: scene.yaml\nmotion: {sinusoids: [{joints: [head], amplitude: 3}]}\n");
  expect_error(deep, {"'motion.sinusoids[0].amplitude'"});
  const fs::path part = dir.write("part.yaml", "scene: scene.yaml\nmotion: {sinusoid: []}\n");
  expect_error(part, {"'motion.sinusoid'"});
  const fs::path ok = dir.write("ok.yaml", "scene: scene.yaml\n");
  expect_error(ok, {"'camera.link'"}, {"camera.link=x"});
}

TEST(Scenario, WrongTypesAreNamed) {
  const test::TestDir dir("scenario_wrong_types");
  const fs::path f = dir.write("s.yaml", "scene: scene.yaml\n");
  expect_error(f, {f.string(), "'duration_s'", "number"}, {"duration_s=abc"});
  expect_error(f, {"'methods'"}, {"methods=full_fusion"});
  expect_error(f, {"'motion'", "map"}, {"motion=[1, 2]"});
  expect_error(f, {"'encoders[0].joints'"}, {"encoders=[{joints: left_arm}]"});
  expect_error(f, {"'miscalibration.camera_offset.xyz_m'", "3 numbers"},
               {"miscalibration.camera_offset.xyz_m=[1, 2]"});
  expect_error(f, {"'runs'", "whole number"}, {"runs=1.5"});
}

TEST(Scenario, ImpossibleValuesAreNamed) {
  const test::TestDir dir("scenario_impossible");
  const fs::path f = dir.write("s.yaml", "scene: scene.yaml\n");
  expect_error(f, {f.string(), "'duration_s'", "out of range"}, {"duration_s=-1"});
  expect_error(f, {"'runs'"}, {"runs=0"});
  expect_error(f, {"'methods'", "kalman"}, {"methods=[kalman]"});
  expect_error(f, {"'methods'", "twice"}, {"methods=[full_fusion, full_fusion]"});
  expect_error(f, {"'motion.sinusoids[0].joints'", "left_arm_joint_9"},
               {"motion.sinusoids=[{joints: [left_arm_joint_9]}]"});
  expect_error(f, {"'encoders[0].joints'", "legs"}, {"encoders=[{joints: [legs], offset_deg: 1}]"});
  expect_error(f, {"'motion.sinusoids[0]'", "twice"},
               {"motion.sinusoids=[{joints: [left_arm, left_arm_joint_1]}]"});
  expect_error(
      f, {"'motion.waypoints[0]'", "limit"},
      {"motion.waypoints=[{joints: [head_pan_joint], times_s: [1], positions_deg: [[170]]}]"});
  expect_error(f, {"'motion.out_of_view[0]'", "return_s"},
               {"motion.out_of_view=[{joints: [head], out_of_view_deg: [1, 1], leave_s: 5, "
                "return_s: 5.5, move_duration_s: 1}]"});
  expect_error(f, {"'loads[0].link'", "hand"},
               {"loads=[{link: hand, mass_kg: 1, start_s: 0, end_s: 2}]"});
  expect_error(f, {"'loads[0].end_s'"},
               {"loads=[{link: left_ee, mass_kg: 1, start_s: 2, end_s: 2.5, ramp_s: 0.5}]"});
  expect_error(f, {"'encoders'", "left_arm_joint_1"},
               {"encoders=[{joints: [arms], step_amplitude_deg: 1}, {joints: [left_arm], "
                "step_amplitude_deg: 2}]"});
  expect_error(f, {"'encoders[0]'", "step_ramp_time_s"},
               {"encoders=[{step_amplitude_deg: 1, step_period_s: 2, step_ramp_time_s: 1.5}]"});
  expect_error(f, {"'camera.far_m'"}, {"camera.near_m=2", "camera.far_m=1"});
  expect_error(f, {"'camera.drop_probability'"}, {"camera.drop_probability=1"});
  expect_error(f, {"'camera.depth_scale_error'"}, {"camera.depth_scale_error=-0.5"});
  expect_error(f, {"'camera.focal_error'"}, {"camera.focal_error=.nan"});
  expect_error(f, {"'miscalibration.head_error.neck'"},
               {"miscalibration.head_error={neck: {xyz_m: [0, 0, 0.01]}}"});
  expect_error(f, {"'model_mismatch.shape_scale.left_arm_fore'"},
               {"model_mismatch.shape_scale={left_arm_fore: 0}"});
  expect_error(f, {"'occluders[0].keyframes[1].time_s'"},
               {"occluders=[{name: o, size_m: [1, 1, 1], keyframes: [{time_s: 2}, {time_s: 1}]}]"});
  expect_error(f, {"'occluders[0].keyframes'"}, {"occluders=[{name: o, size_m: [1, 1, 1]}]"});
  expect_error(f, {"'scoring.end_effectors'", "nose"}, {"scoring.end_effectors=[nose]"});
  expect_error(f, {f.string(), "'scoring.lost_threshold_m'", "out of range"},
               {"scoring.lost_threshold_m=0"});
  expect_error(f, {f.string(), "'scoring.lost_after_s'", "out of range"},
               {"scoring.lost_after_s=-1"});
  expect_error(f, {f.string(), "'scoring.lost_after_s'", "number"}, {"scoring.lost_after_s=long"});
  expect_error(f, {"'scene'"}, {"scene=missing.yaml"});
  expect_error(f,
               {f.string(), "key 'tracker_overrides.particle_filter.particles' must be a number"},
               {"tracker_overrides={particle_filter.particles: {a: 1}}"});
  expect_error(f,
               {f.string(),
                "key 'tracker_overrides.particle_filter.particles' = 0 is out of range "
                "[1, 1000000]"},
               {"tracker_overrides={particle_filter.particles: 0}"});
  expect_error(f, {f.string(), "key 'tracker_overrides.joints.per_joint.a.bias_decay_per_s' = 2"},
               {"tracker_overrides={joints.per_joint.a: {bias_decay_per_s: 2}}"});
  expect_error(f, {"'tracker_overrides.particle_filter.particles'", "not a map"},
               {"tracker_overrides={particle_filter: 3, particle_filter.particles: 1}"});
}

// arm7's fingers are a prismatic joint: an encoder group's degree keys
// corrupt its revolute joints and its metre keys the fingers; a group with
// only degree keys that takes in the fingers is an error naming them (until
// stop 71 a finger read "0.057 degrees" of noise as 1 mm). Motion keys are
// all in degrees, so a motion group that takes in a finger is an error.
TEST(Scenario, EncoderKeysComeInTheJointsUnits) {
  const fs::path f = fs::path(ARTTRACK_SOURCE_DIR) / "scenarios" / "arm7" / "constant_bias.yaml";
  expect_error(f,
               {f.string(), "'encoders[1].joints'", "'arm7_finger_joint1'", "noise_deg", "noise_m"},
               {"encoders=[{joints: [arm], offset_deg: 8.6}, {joints: [all], noise_deg: 0.057}]"});
  expect_error(f, {"'encoders[0].noise_m'", "prismatic"},
               {"encoders=[{joints: [arm], noise_m: 0.001}]"});
  expect_error(f, {"'encoders[0].offset_deg'", "revolute"},
               {"encoders=[{joints: [arm7_finger_joint1], offset_deg: 1, noise_m: 0.001}]"});
  expect_error(f, {"'encoders[0].noise_m'", "out of range"},
               {"encoders=[{joints: [arm7_finger_joint1], noise_m: -1}]"});
  // Motion keys are in degrees too, and motion moves revolute joints only.
  expect_error(f, {f.string(), "'motion.random[0].joints'", "'arm7_finger_joint1'", "degrees"},
               {"motion.random=[{joints: [all], amplitude_deg: 15}]"});
  expect_error(f, {"'motion.sinusoids[0].joints'", "'arm7_finger_joint2'"},
               {"motion.sinusoids=[{joints: [arm7_finger_joint2], amplitude_deg: 1}]"});

  const Scenario s =
      load_scenario(f, {"encoders=[{noise_deg: 0.057, noise_m: 0.0001, resolution_m: 1e-5}]"});
  ASSERT_EQ(s.encoders.groups.size(), 2u);
  const EncoderGroupCorruption& revolute = s.encoders.groups[0];
  const EncoderGroupCorruption& prismatic = s.encoders.groups[1];
  EXPECT_EQ(revolute.joints.size(), s.urdf.movable_joints.size() - 1);
  EXPECT_DOUBLE_EQ(revolute.noise_sigma_rad, 0.057 * kRadPerDeg);
  EXPECT_EQ(revolute.resolution_rad, 0.0);
  EXPECT_EQ(prismatic.joints, (std::vector<std::string>{"arm7_finger_joint1"}));
  EXPECT_DOUBLE_EQ(prismatic.noise_sigma_rad, 0.0001);
  EXPECT_DOUBLE_EQ(prismatic.resolution_rad, 1e-5);

  // Stated exact, the fingers need no group of their own to be left alone.
  const Scenario exact = load_scenario(f, {"encoders=[{noise_deg: 0.057, noise_m: 0}]"});
  ASSERT_EQ(exact.encoders.groups.size(), 2u);
  EXPECT_EQ(exact.encoders.groups[1].noise_sigma_rad, 0.0);
}

// model_mismatch.random: the candidates read (groups expanded, a fixed
// joint by name), and run_model_error's draws within the budget: the
// counts asked, sizes in their range with both signs, every candidate
// drawn over many seeds, the same seed the same robot, on top of the
// scenario's fixed mismatch.
TEST(Scenario, RandomModelErrorIsDrawnPerSeedWithinItsBudget) {
  const test::TestDir dir("scenario_random_mismatch");
  const fs::path f = dir.write("full.yaml", kFull);
  const Scenario s = load_scenario(
      f, {"model_mismatch.random={joints: [arms, left_ee_joint], lengths: 2, length_m: [0.004, "
          "0.006], links: [left_arm_fore, right_arm_upper], scales: 1, scale: [0.03, 0.05]}"});
  const RandomModelMismatch& r = s.random_mismatch;
  EXPECT_EQ(r.joints,
            (std::vector<std::string>{"left_arm_joint_1", "left_arm_joint_2", "right_arm_joint_1",
                                      "right_arm_joint_2", "left_ee_joint"}));
  EXPECT_EQ(r.lengths, 2);
  EXPECT_EQ(r.scales, 1);
  EXPECT_EQ(r.length_min_m, 0.004);
  EXPECT_EQ(r.scale_max, 0.05);

  std::map<std::string, int> drawn;
  int shorter = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const DrawnModelError d = run_model_error(s, seed);
    ASSERT_EQ(d.link_lengths_m.size(), 2u);
    ASSERT_EQ(d.shape_scales.size(), 1u);
    for (const auto& [joint, m] : d.link_lengths_m) {
      ++drawn[joint];
      shorter += m < 0;
      EXPECT_GE(std::abs(m), 0.004);
      EXPECT_LE(std::abs(m), 0.006);
      // Added to the file's own 10 mm on left_arm_joint_2.
      const double fixed = joint == "left_arm_joint_2" ? 0.01 : 0.0;
      EXPECT_DOUBLE_EQ(d.perturbation.origin_extension_m.at(joint), fixed + m);
    }
    for (const auto& [link, scale] : d.shape_scales) {
      ++drawn[link];
      EXPECT_GE(std::abs(scale - 1), 0.03 - 1e-12);
      EXPECT_LE(std::abs(scale - 1), 0.05 + 1e-12);
      const double fixed = link == "left_arm_fore" ? 1.1 : 1.0;
      EXPECT_DOUBLE_EQ(d.perturbation.link_scale.at(link), fixed * scale);
    }
    const DrawnModelError again = run_model_error(s, seed);
    EXPECT_EQ(again.link_lengths_m, d.link_lengths_m);
    EXPECT_EQ(again.shape_scales, d.shape_scales);
  }
  EXPECT_EQ(drawn.size(), 7u);  // five joints, two links
  EXPECT_GT(shorter, 100);
  EXPECT_LT(shorter, 300);
  EXPECT_NE(run_model_error(s, 1).link_lengths_m, run_model_error(s, 2).link_lengths_m);

  // Without model_mismatch.random: the file's robot, nothing drawn.
  const DrawnModelError fixed = run_model_error(load_scenario(f), 7);
  EXPECT_TRUE(fixed.link_lengths_m.empty() && fixed.shape_scales.empty());
  EXPECT_EQ(fixed.perturbation.origin_extension_m.at("left_arm_joint_2"), 0.01);

  expect_error(f, {"'model_mismatch.random.lengths'"},
               {"model_mismatch.random={joints: [left_arm], lengths: 3, length_m: [0.004, "
                "0.006]}"});
  expect_error(f, {"'model_mismatch.random.length_m'", "[min, max]"},
               {"model_mismatch.random={joints: [left_arm], lengths: 1, length_m: [0.006, "
                "0.004]}"});
  expect_error(f, {"'model_mismatch.random.length_m'", "required"},
               {"model_mismatch.random={joints: [left_arm], lengths: 1}"});
  expect_error(f, {"'model_mismatch.random.links'", "hand"},
               {"model_mismatch.random={links: [hand], scales: 1, scale: [0.01, 0.02]}"});
  expect_error(f, {"'model_mismatch.random.joints'", "elbow"},
               {"model_mismatch.random={joints: [elbow], lengths: 1, length_m: [0, 0.01]}"});
  expect_error(f, {"'model_mismatch.random.scale'"},
               {"model_mismatch.random={links: [left_arm_fore], scales: 1, scale: [0.1, 0.9]}"});
  expect_error(f, {"'model_mismatch.random.lenghts'", "not a known key"},
               {"model_mismatch.random={lenghts: 1}"});
}

TEST(Scenario, JointGroups) {
  const std::vector<std::string> joints{"left_arm_joint_1", "left_arm_joint_2", "right_arm_joint_1",
                                        "head_pan_joint", "torso_joint"};
  const std::map<std::string, std::vector<std::string>> groups{
      {"left_arm", {"left_arm_joint_1", "left_arm_joint_2"}}, {"head", {"head_pan_joint"}}};
  EXPECT_EQ(expand_joint_group("left_arm", joints, groups),
            (std::vector<std::string>{"left_arm_joint_1", "left_arm_joint_2"}));
  EXPECT_EQ(expand_joint_group("head", joints, groups),
            (std::vector<std::string>{"head_pan_joint"}));
  EXPECT_EQ(expand_joint_group("all", joints, groups), joints);
  EXPECT_EQ(expand_joint_group("all", joints, {}), joints);
  EXPECT_EQ(expand_joint_group("torso_joint", joints, groups),
            (std::vector<std::string>{"torso_joint"}));
  // No group is built in but `all`.
  EXPECT_TRUE(expand_joint_group("right_arm", joints, groups).empty());
  EXPECT_TRUE(expand_joint_group("left_arm", joints, {}).empty());
}

// The scene declares the groups (members may be groups declared before) and
// the robot's tracker settings; both are checked.
TEST(Scenario, SceneGroupsAndTrackerOverrides) {
  const test::TestDir dir("scenario_scene_groups");
  const fs::path f = dir.write("s.yaml", "scene: scene.yaml\nencoders: [{joints: [arms]}]\n");
  const Scenario s = load_scenario(f);
  EXPECT_EQ(s.scene.joint_groups.at("arms"),
            (std::vector<std::string>{"left_arm_joint_1", "left_arm_joint_2", "right_arm_joint_1",
                                      "right_arm_joint_2"}));
  ASSERT_EQ(s.encoders.groups.size(), 1u);
  EXPECT_EQ(s.encoders.groups[0].joints.size(), 4u);
  EXPECT_EQ(s.tracker.joint_overrides.at("head_pan_joint").estimate_bias, false);
  // The scenario's tracker_overrides win over the scene's.
  const Scenario t =
      load_scenario(f, {"tracker_overrides={joints.per_joint.head_pan_joint.estimate_bias: true}"});
  EXPECT_EQ(t.tracker.joint_overrides.at("head_pan_joint").estimate_bias, true);

  std::string scene = test::kSceneYaml;
  const auto at = scene.find("    arms:");
  dir.write("bad_scene.yaml", scene.substr(0, at) + "    legs: [knee_joint]\n" + scene.substr(at));
  expect_error(dir.write("b.yaml", "scene: bad_scene.yaml\n"),
               {"bad_scene.yaml", "'robot.groups.legs'", "knee_joint", "not a movable joint"});
  dir.write("bad_scene.yaml",
            scene.substr(0, at) + "    all: [head_pan_joint]\n" + scene.substr(at));
  expect_error(dir.write("b.yaml", "scene: bad_scene.yaml\n"),
               {"bad_scene.yaml", "'robot.groups.all'", "always every movable joint"});
  dir.write("bad_scene.yaml",
            scene.substr(0, at) + "    head_pan_joint: [head_tilt_joint]\n" + scene.substr(at));
  expect_error(dir.write("b.yaml", "scene: bad_scene.yaml\n"),
               {"bad_scene.yaml", "'robot.groups.head_pan_joint'", "also a joint"});
  const auto over = scene.find("  tracker_overrides:");
  dir.write("bad_scene.yaml", scene.substr(0, over) +
                                  "  tracker_overrides: {particle_filter.particles: 0}\n" +
                                  scene.substr(scene.find("camera:")));
  expect_error(
      dir.write("b.yaml", "scene: bad_scene.yaml\n"),
      {"bad_scene.yaml: key 'robot.tracker_overrides.particle_filter.particles' = 0 is out "
       "of range"});
  // A bad tracker file is named as such, though the scene has tracker_overrides.
  const fs::path tracker = dir.write("t.yaml", "depth_model: {max_range_m: 200}\n");
  try {
    load_scenario(dir.write("d.yaml", "scene: scene.yaml\ntracker: t.yaml\n"));
    ADD_FAILURE() << "no error for a bad tracker file";
  } catch (const InputError& e) {
    EXPECT_EQ(
        std::string(e.what()),
        tracker.string() + ": key 'depth_model.max_range_m' = 200 is out of range [0.1, 100]");
  }
  // A group the scene does not declare: the error lists those it does.
  expect_error(dir.write("c.yaml", "scene: scene.yaml\nencoders: [{joints: [legs]}]\n"),
               {"'encoders[0].joints'", "legs", "all, arms, head, left_arm, right_arm"});
}

TEST(Scenario, OccluderScheduleInterpolates) {
  OccluderSchedule s;
  Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = Eigen::Isometry3d::Identity();
  b.translation() << 2, 0, 0;
  b.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  s.keyframes = {{1.0, a}, {3.0, b}};
  EXPECT_TRUE(s.pose_at(0.0).isApprox(a));  // held before the first
  EXPECT_TRUE(s.pose_at(5.0).isApprox(b));  // and after the last
  const Eigen::Isometry3d mid = s.pose_at(2.0);
  EXPECT_NEAR(mid.translation().x(), 1.0, 1e-15);
  EXPECT_NEAR(Eigen::AngleAxisd(mid.linear()).angle(), M_PI / 4, 1e-12);
}

TEST(Scenario, LoadRampsInAndOut) {
  LinkLoad l;
  l.start_s = 1;
  l.end_s = 5;
  l.ramp_s = 1;
  EXPECT_EQ(l.weight(0.5), 0.0);
  EXPECT_NEAR(l.weight(1.5), 0.5, 1e-12);
  EXPECT_EQ(l.weight(3.0), 1.0);
  EXPECT_NEAR(l.weight(4.5), 0.5, 1e-12);
  EXPECT_EQ(l.weight(5.5), 0.0);
}

// Every scenario shipped with the project loads (its scene, robot and
// tracker configuration included), in every folder; all of the dual-arm
// robot's show both arms, so all of them score both hands.
TEST(Scenario, ShippedScenariosLoad) {
  const fs::path dir = fs::path(ARTTRACK_SOURCE_DIR) / "scenarios";
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    // The realistic family's camera and robot fragments, merged into its
    // files by `extends`, are not scenarios on their own (no scene).
    if (entry.path().parent_path() == dir / "realistic" / "base") continue;
    SCOPED_TRACE(entry.path().string());
    const Scenario s = load_scenario(entry.path());
    EXPECT_FALSE(s.methods.empty());
    // Both arms are in view: both hands are scored (the second robot: its one hand).
    if (entry.path().parent_path().filename() == "arm7" ||
        entry.path().filename().string().starts_with("arm7_"))
      EXPECT_EQ(s.scoring.end_effectors, (std::vector<std::string>{"arm7_ee"}));
    else
      EXPECT_EQ(s.scoring.end_effectors, (std::vector<std::string>{"left_ee", "right_ee"}));
    ++count;
  }
  EXPECT_GE(count, 36 + 2 + 16);  // the paper's, cable stretch's and the realistic files at least
  EXPECT_TRUE(fs::exists(default_scenario_path()));
}

}  // namespace
}  // namespace arttrack::sim
