// The scenario runner end to end on a small dual-arm robot (160x120 camera,
// the tracker's 80x60 likelihood, a few simulated seconds):
//   - encoders only is exactly forward kinematics of the biased readings:
//     its error at every sample equals the error of the nominal model's FK
//     at (true angle + true bias) in the nominal camera, computed here
//     independently, and the 8.6 degree bias costs centimetres;
//   - full fusion's error falls well below that;
//   - a load on the hand changes the cable-stretch bias by compliance x m g x
//     lever arm (closed form);
//   - the occlusion ground truth is 0 with the wall away, 1 behind it, in
//     between for a half wall;
//   - the same seed gives identical numbers, another seed different ones;
//   - `arttrack render` of a scenario draws the robot its run simulates.
#include "arttrack/sim/scenario_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "../error_of.h"
#include "arttrack/sim/depth_compare.h"
#include "arttrack/sim/run_outputs.h"
#include "arttrack/sim/scene_render.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"
#include "arttrack/tracker/units.h"
#include "scenario_test_robot.h"

namespace arttrack::sim {
namespace {

namespace fs = std::filesystem;

constexpr char kBiasScenario[] = R"(
scene: scene.yaml
duration_s: 4
seed: 11
methods: [encoders_only, full_fusion]
motion:
  sinusoids:
    - {joints: [left_arm_joint_1], amplitude_deg: 15, frequency_hz: 0.3, fade_in_s: 0.5}
    - {joints: [left_arm_joint_2], amplitude_deg: 20, frequency_hz: 0.2, phase_deg: 90, fade_in_s: 0.5}
encoders:
  - {joints: [arms], offset_deg: 8.6}
miscalibration:
  camera_offset: {xyz_m: [0.01, -0.01, 0.02], rpy_deg: [1, -1, 0.5]}
scoring: {converged_after_s: 2.5, end_effectors: [left_ee]}
# Encoders only then reports the raw readings, which the test checks exactly.
tracker_overrides: {encoder_smoothing.enabled: false}
)";

std::size_t index_of(const std::vector<std::string>& names, const std::string& name) {
  return std::size_t(std::find(names.begin(), names.end(), name) - names.begin());
}

TEST(ScenarioRunner, EncodersOnlyShowsTheBiasAndFullFusionRemovesIt) {
  const test::TestDir dir("runner_bias");
  const Scenario scenario = load_scenario(dir.write("bias.yaml", kBiasScenario));
  const ScenarioResult r = run_scenario(scenario);
  ASSERT_EQ(r.methods, (std::vector<std::string>{"encoders_only", "full_fusion"}));
  ASSERT_EQ(r.runs.size(), 1u);
  const RunResult& run = r.runs[0];
  EXPECT_EQ(run.frames_captured, 121);  // 30 Hz over [0, 4] s
  EXPECT_EQ(run.frames_delivered, 121);
  ASSERT_EQ(run.truth.size(), 121u);

  // Encoders only = the nominal model's FK at true angle + true bias, seen
  // from the nominal camera; the truth is the simulator's (true camera).
  RobotModelOptions options;
  options.add_virtual_camera_joints = false;
  const RobotModel nominal =
      RobotModel::from_urdf_file((dir.path() / "robot.urdf").string(), options);
  KinematicsState state(nominal);
  const int ee = nominal.link_index("left_ee");
  for (std::size_t i = 0; i < run.truth.size(); ++i) {
    const TruthSample& t = run.truth[i];
    Eigen::VectorXd q = Eigen::VectorXd::Zero(nominal.num_joints());
    for (std::size_t j = 0; j < r.joint_names.size(); ++j)
      q[nominal.joint_index(r.joint_names[j])] = t.angle_rad[j] + t.bias_rad[j];
    forward_kinematics(nominal, q, state);
    const PoseError expected = pose_error(T_camera_link(nominal, state, ee), t.T_camera_ee[0]);
    const EstimateSample& s = run.methods[0].samples[i];
    EXPECT_NEAR(s.ee_error[0].translation_m, expected.translation_m, 1e-9) << "t " << t.time_s;
    EXPECT_NEAR(s.ee_error[0].rotation_rad, expected.rotation_rad, 1e-9) << "t " << t.time_s;
    // The true bias is the injected offset on the arms, none on the head.
    EXPECT_NEAR(t.bias_rad[index_of(r.joint_names, "left_arm_joint_1")], 8.6 * kRadPerDeg, 1e-15);
    EXPECT_EQ(t.bias_rad[index_of(r.joint_names, "head_pan_joint")], 0.0);
    EXPECT_TRUE(std::isnan(t.occluded_fraction));  // no occluders: not rendered
  }

  // The camera, scored against the simulator's: the scenario's offset is
  // the TRUE camera in the nominal one (URDF convention, R = Rz Ry Rx).
  Eigen::Isometry3d T_nominal_true = Eigen::Isometry3d::Identity();
  T_nominal_true.translation() << 0.01, -0.01, 0.02;
  T_nominal_true.linear() = (Eigen::AngleAxisd(0.5 * kRadPerDeg, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(-1 * kRadPerDeg, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(1 * kRadPerDeg, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const PoseError offset_error = pose_error(Eigen::Isometry3d::Identity(), T_nominal_true);
  EXPECT_NEAR(offset_error.translation_m, std::sqrt(0.0006), 1e-15);
  for (const TruthSample& t : run.truth) {
    ASSERT_TRUE(t.T_base_camera.has_value());
    // The true offset in the virtual joints' convention reproduces that transform.
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = t.camera_offset.head<3>();
    T.linear() = (Eigen::AngleAxisd(t.camera_offset[3], Eigen::Vector3d::UnitX()) *
                  Eigen::AngleAxisd(t.camera_offset[4], Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(t.camera_offset[5], Eigen::Vector3d::UnitZ()))
                     .toRotationMatrix();
    EXPECT_TRUE(T.isApprox(T_nominal_true, 1e-9)) << t.time_s;
  }
  for (const EstimateSample& s : run.methods[0].samples) {
    // Encoders only does not correct the camera, and the head's encoders
    // are exact: its camera error is the whole offset.
    EXPECT_EQ(s.camera_offset, CameraOffset::Zero());
    EXPECT_NEAR(s.camera_error.translation_m, offset_error.translation_m, 1e-9);
    EXPECT_NEAR(s.camera_error.rotation_rad, offset_error.rotation_rad, 1e-9);
  }

  const MethodSummary& enc = r.method("encoders_only")->summary;
  const MethodSummary& fusion = r.method("full_fusion")->summary;
  EXPECT_NEAR(enc.all.camera_translation_m.p50, offset_error.translation_m, 1e-9);
  EXPECT_EQ(enc.all.camera_translation_m.count, 121u);
  // Full fusion corrects the camera (better than no correction).
  EXPECT_LT(fusion.converged.camera_translation_m.p50, offset_error.translation_m);
  // Consistency: encoders only estimates neither biases nor the camera
  // (not 0%, unknown); its angles claim the encoder noise plus the bias
  // prior (10 degrees stationary), so the arms' 8.6 degrees are within two
  // standard deviations, as the exact head's are: 6 of 6.
  EXPECT_EQ(enc.all.bias_coverage.estimated, 0u);
  EXPECT_EQ(enc.all.camera_offset_coverage.estimated, 0u);
  EXPECT_NEAR(enc.all.angle_coverage.fraction(), 1.0, 1e-12);
  EXPECT_GT(fusion.all.bias_coverage.estimated, 0u);
  EXPECT_GT(fusion.all.camera_offset_coverage.estimated, 0u);
  // Every sample's end-effector pose has a covariance: three position and
  // three rotation components per sample and end effector.
  for (const MethodSummary* m : {&enc, &fusion}) {
    EXPECT_EQ(m->all.end_effector_position_coverage.estimated,
              3 * m->all.translation_m.count * m->end_effectors.size());
    EXPECT_EQ(m->all.end_effector_rotation_coverage.estimated,
              m->all.end_effector_position_coverage.estimated);
  }
  EXPECT_GT(enc.all.translation_m.p50, 0.03);  // centimetres
  EXPECT_LT(fusion.converged.translation_m.p50, 0.2 * enc.converged.translation_m.p50);
  EXPECT_LT(fusion.converged.translation_m.p50, 0.015);
  EXPECT_GT(fusion.converged.reference.compared, 0u);  // compared with encoders only
  EXPECT_LT(fusion.converged.reference.share_worse(), 0.05);

  // Timings and kept frames for the report.
  const MethodTiming& timing = r.method("full_fusion")->timing;
  EXPECT_EQ(timing.joint_update_us.count, 4001u);
  EXPECT_EQ(timing.image_update_ms.count, 121u);
  EXPECT_GT(timing.evaluations_per_image, 0);
  // The tracker's counts of what it did: full fusion searched at its first
  // image and took Gauss-Newton steps; encoders only did neither.
  const HealthCounts& counts = r.method("full_fusion")->counts;
  EXPECT_EQ(counts.runs, 1);
  EXPECT_GE(counts.acquisitions, 1);
  EXPECT_GT(counts.refinements_accepted, 0);
  EXPECT_EQ(counts.hand_searches, run.methods[1].samples.back().health.hand_searches);
  EXPECT_EQ(r.method("encoders_only")->counts.acquisitions, 0);
  ASSERT_EQ(r.frames.size(), 4u);
  for (const KeptFrame& f : r.frames) {
    EXPECT_EQ(f.observed.width, 160);
    EXPECT_EQ(f.estimate_method, "full_fusion");
    EXPECT_GT(std::count_if(f.estimate.depth_m.begin(), f.estimate.depth_m.end(),
                            [](float z) { return z > 0; }),
              1000);
  }

  // The CSV has one row per sample and method plus the header.
  std::stringstream csv;
  write_timeseries_csv(csv, r);
  EXPECT_EQ(std::count(std::istreambuf_iterator<char>(csv), {}, '\n'), 1 + 2 * 121);
  // Per end effector, its error's six components (their norms are the
  // scored errors), their reported standard deviations and the fit's
  // correction (full fusion's only).
  const TimeseriesTable table = timeseries_table(r);
  const auto column = [&](const std::string& name) -> const TimeseriesColumn& {
    for (const TimeseriesColumn& c : table.columns)
      if (c.name == name) return c;
    ADD_FAILURE() << "no column " << name;
    return table.columns.front();
  };
  const TimeseriesColumn& method = column("method");
  double largest_correction_m[2] = {0, 0};
  for (std::size_t row = 0; row < table.rows; ++row) {
    const Eigen::Vector3d error(column("left_ee_err_x_m").numbers[row],
                                column("left_ee_err_y_m").numbers[row],
                                column("left_ee_err_z_m").numbers[row]);
    EXPECT_NEAR(error.norm(), column("translation_m_left_ee").numbers[row], 1e-12);
    EXPECT_GT(column("left_ee_std_rz_rad").numbers[row], 0);
    largest_correction_m[method.text[row] == "full_fusion"] =
        std::max(largest_correction_m[method.text[row] == "full_fusion"],
                 std::abs(column("left_ee_correction_x_m").numbers[row]));
  }
  EXPECT_EQ(largest_correction_m[0], 0.0);  // encoders only
  EXPECT_GT(largest_correction_m[1], 0.0);
  const std::string json = summary_json(r);
  for (const char* key :
       {"\"scenario\": \"bias\"", "\"converged_translation_m\"", "\"convergence_time_s\"",
        "\"evaluations_per_image\"", "\"p99\"", "\"end_effectors\"", "\"left_ee\"", "\"lost\"",
        "\"camera\"", "\"consistency\"", "\"bias_within_2sigma\"", "\"left_arm_joint_1\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
}

// A hand load ramps in; the arm is held horizontal, so joint 1 carries an
// extra m g L and its encoder's cable stretch grows by compliance m g L.
TEST(ScenarioRunner, LoadStretchesTheCable) {
  const test::TestDir dir("runner_load");
  const Scenario scenario = load_scenario(dir.write("load.yaml", R"(
scene: scene.yaml
duration_s: 2.5
methods: [encoders_only]
loads: [{link: left_ee, mass_kg: 2, start_s: 0.5, end_s: 2.5, ramp_s: 0.2}]
encoders: [{joints: [left_arm_joint_1], compliance_deg_per_Nm: 0.5, stretch_time_constant_s: 0.05}]
)"));
  const ScenarioResult r = run_scenario(scenario);
  const std::size_t j = index_of(r.joint_names, "left_arm_joint_1");
  const std::vector<TruthSample>& truth = r.runs[0].truth;
  auto bias_at = [&](double t_s) {
    for (const TruthSample& s : truth)
      if (s.time_s >= t_s) return s.bias_rad[j];
    return std::numeric_limits<double>::quiet_NaN();
  };
  const double expected = 0.5 * kRadPerDeg * 2 * 9.81 * 0.55;
  EXPECT_NEAR(std::abs(bias_at(2.0) - bias_at(0.4)), expected, 0.03 * expected);
}

TEST(ScenarioRunner, OcclusionGroundTruth) {
  const test::TestDir dir("runner_occlusion");
  // A wall 0.4 m in front of the camera along its view (40 degrees down),
  // far to the side until 1 s, then covering the +y half, then all of it.
  const Scenario scenario = load_scenario(dir.write("wall.yaml", R"(
scene: scene.yaml
duration_s: 2
methods: [encoders_only]
occluders:
  - name: wall
    type: box
    size_m: [0.1, 3, 3]
    keyframes:
      - {time_s: 0, position_m: [-0.144, 10, 1.343]}
      - {time_s: 1.0, position_m: [-0.144, 10, 1.343]}
      - {time_s: 1.001, position_m: [-0.144, 1.5, 1.343]}
      - {time_s: 1.5, position_m: [-0.144, 1.5, 1.343]}
      - {time_s: 1.501, position_m: [-0.144, 0, 1.343]}
)"));
  const ScenarioResult r = run_scenario(scenario);
  for (const TruthSample& s : r.runs[0].truth) {
    SCOPED_TRACE(s.time_s);
    if (s.time_s < 1.0) {
      EXPECT_EQ(s.occluded_fraction, 0.0);
    } else if (s.time_s > 1.01 && s.time_s < 1.5) {
      EXPECT_GT(s.occluded_fraction, 0.2);
      EXPECT_LT(s.occluded_fraction, 0.8);
    } else if (s.time_s > 1.51) {
      EXPECT_EQ(s.occluded_fraction, 1.0);
    }
  }
}

// model_mismatch.random: each run simulates its own robot. With the left
// forearm's origin drawn 10 mm longer or shorter, two runs that drew
// opposite signs hold the hand 20 mm apart at the same angles, runs that
// drew the same sign in the same place; summary.json names each run's draw.
TEST(ScenarioRunner, EachRunSimulatesTheRobotItDrew) {
  const test::TestDir dir("runner_random_robots");
  const Scenario scenario = load_scenario(dir.write("robots.yaml", R"(
scene: scene.yaml
duration_s: 0.2
runs: 6
methods: [encoders_only]
scoring: {end_effectors: [left_ee]}
model_mismatch:
  random: {joints: [left_arm_joint_2], lengths: 1, length_m: [0.01, 0.01]}
)"));
  const ScenarioResult r = run_scenario(scenario);
  ASSERT_EQ(r.runs.size(), 6u);
  std::vector<double> drawn_m;
  std::vector<Eigen::Vector3d> hand_m;
  for (const RunResult& run : r.runs) {
    ASSERT_EQ(run.drawn_link_lengths_m.size(), 1u);
    drawn_m.push_back(run.drawn_link_lengths_m.at("left_arm_joint_2"));
    EXPECT_NEAR(std::abs(drawn_m.back()), 0.01, 1e-12);
    EXPECT_TRUE(run.drawn_shape_scales.empty());
    hand_m.push_back(run.truth.front().T_camera_ee.at(0).translation());
  }
  int opposite = 0, same = 0;
  for (std::size_t a = 0; a < drawn_m.size(); ++a)
    for (std::size_t b = 0; b < a; ++b) {
      const double apart_m = (hand_m[a] - hand_m[b]).norm();
      if (drawn_m[a] == drawn_m[b]) {
        EXPECT_LT(apart_m, 1e-3) << "runs " << a << " and " << b;
        ++same;
      } else {
        EXPECT_NEAR(apart_m, 0.02, 1e-3) << "runs " << a << " and " << b;
        ++opposite;
      }
    }
  EXPECT_GT(opposite, 0);
  EXPECT_GT(same, 0);
  const std::string json = summary_json(r);
  EXPECT_NE(json.find("\"robots\""), std::string::npos);
  EXPECT_NE(json.find("\"left_arm_joint_2\""), std::string::npos);
}

// A joint whose origin has no translation has no length to draw: the
// scenario is refused before its first run, naming the key, the URDF and
// the joint, whichever joints a seed would have drawn.
TEST(ScenarioRunner, RandomLengthOfAJointWithoutTranslationIsRefusedBeforeAnyRun) {
  const test::TestDir dir("runner_random_no_translation");
  std::string urdf = test::kRobotUrdf;
  const std::string elbow = R"(<origin xyz="0.3 0 0"/><axis xyz="0 0 1"/>)";
  const std::size_t at = urdf.find(elbow);  // left_arm_joint_2, the first
  ASSERT_NE(at, std::string::npos);
  urdf.replace(at, elbow.size(), R"(<origin xyz="0 0 0"/><axis xyz="0 0 1"/>)");
  dir.write("robot.urdf", urdf);
  // Two runs, each drawing one of `joints`' lengths.
  auto drawing = [&](const std::string& file, const std::string& joints) {
    return load_scenario(dir.write(file, R"(
scene: scene.yaml
duration_s: 0.2
runs: 2
methods: [encoders_only]
scoring: {end_effectors: [left_ee]}
model_mismatch:
  random: {joints: [)" + joints + R"(], lengths: 1, length_m: [0.004, 0.006]}
)"));
  };
  const std::string error = test_support::error_of(
      [&] { run_scenario(drawing("robots.yaml", "left_arm_joint_1, left_arm_joint_2")); });
  EXPECT_NE(error.find("robots.yaml"), std::string::npos) << error;
  EXPECT_NE(error.find("model_mismatch.random"), std::string::npos) << error;
  EXPECT_NE(error.find("robot.urdf"), std::string::npos) << error;
  EXPECT_NE(error.find("'left_arm_joint_2'"), std::string::npos) << error;
  EXPECT_NE(error.find("no translation"), std::string::npos) << error;
  // The same draw from joints with a length runs.
  EXPECT_EQ(run_scenario(drawing("fine.yaml", "left_arm_joint_1, right_arm_joint_2")).runs.size(),
            2u);
}

// `arttrack render` of a scenario shows the robot its first run simulates,
// and the tracker's nominal robot from the true camera: with the camera
// miscalibrated alone both renders agree, with a forearm 3 cm long they
// do not, by the forearm's length.
TEST(SceneRender, AScenarioRendersTheRobotItSimulatesAgainstTheNominalOne) {
  const test::TestDir dir("render_model_error");
  auto agreement = [&](const std::string& file, const std::string& mismatch) {
    const fs::path path = dir.write(file, R"(
scene: scene.yaml
duration_s: 1
motion:
  random: [{joints: [left_arm], amplitude_deg: 10}]
miscalibration: {camera_offset: {xyz_m: [0.01, -0.015, 0.02], rpy_deg: [0.5, -1.0, 0.8]}}
)" + mismatch);
    const SceneRender r = render_scene(path, 0.5);
    EXPECT_NE(r.model_mismatch.find("camera 26.9 mm"), std::string::npos) << r.model_mismatch;
    EXPECT_EQ(r.model_mismatch.find("joint origins") != std::string::npos, !mismatch.empty())
        << r.model_mismatch;
    return std::pair(compare_depth(r.model_depth, r.robot_depth, 2e-3), r.model_mismatch);
  };
  const auto [exact, exact_text] = agreement("camera_off.yaml", "");
  EXPECT_GT(exact.pixels_both, 1000);
  // Measured: 5476 px, all within 2 mm (0.00 mm apart), IoU 1.
  EXPECT_GT(exact.fraction_within(), 0.999) << exact.summary();
  EXPECT_GT(exact.silhouette_iou(), 0.999) << exact.summary();

  const auto [longer, longer_text] = agreement(
      "forearm_long.yaml", "model_mismatch: {link_lengths_m: {left_arm_joint_2: 0.03}}\n");
  EXPECT_NE(longer_text.find("left_arm_joint_2 +30.0 mm"), std::string::npos) << longer_text;
  // Measured: 17 of 5471 px more than 2 mm apart (27.8 mm at most), IoU
  // 0.996 (the forearm's end, a few pixels at 160x120).
  EXPECT_GE(longer.pixels_both - longer.within_tolerance, 10) << longer.summary();
  EXPECT_LT(longer.silhouette_iou(), 0.999) << longer.summary();
  EXPECT_GT(longer.max_abs_difference_m, 0.02) << longer.summary();
}

// `arttrack render --time T` of a scenario is its first run's scene at the
// joint step nearest T, as the run simulated it: the same physics time step
// and the same loads, so the same true angles to the bit. Render once
// stepped the scene's own time step (2 ms, the run 1 ms) without the loads:
// here 0.027 rad (1.5 degrees) off the run.
TEST(SceneRender, AScenarioRendersItsFirstRunsPoseAtThatJointStep) {
  const test::TestDir dir("render_run_pose");
  const fs::path path = dir.write("loaded.yaml", R"(
scene: scene.yaml
duration_s: 0.8
seed: 3
methods: [encoders_only]
motion:
  random: [{joints: [left_arm], amplitude_deg: 15}]
loads: [{link: left_ee, mass_kg: 2, start_s: 0.1, end_s: 5, ramp_s: 0.2}]
scoring: {every_n_joint_steps: 50, end_effectors: [left_ee]}
)");
  RunOptions options;
  options.runs = 1;
  const ScenarioResult run = run_scenario(load_scenario(path), options);
  double worst_rad = 0;
  int compared = 0;
  for (const double time_s : {0.3, 0.7}) {
    const SceneRender r = render_scene(path, time_s + 0.0004);  // the nearest joint step
    EXPECT_NEAR(r.time_s, time_s, 1e-9);
    const auto sample =
        std::find_if(run.runs[0].truth.begin(), run.runs[0].truth.end(),
                     [&](const TruthSample& t) { return std::abs(t.time_s - time_s) < 1e-9; });
    ASSERT_NE(sample, run.runs[0].truth.end()) << time_s;
    for (std::size_t j = 0; j < run.joint_names.size(); ++j) {
      const auto it = std::find(r.joint_names.begin(), r.joint_names.end(), run.joint_names[j]);
      ASSERT_NE(it, r.joint_names.end()) << run.joint_names[j];
      const double rendered = r.joint_angle_rad[std::size_t(it - r.joint_names.begin())];
      worst_rad = std::max(worst_rad, std::abs(rendered - sample->angle_rad[Eigen::Index(j)]));
      ++compared;
    }
  }
  std::printf("%d angles, render against the run: at most %.3g rad apart\n", compared, worst_rad);
  EXPECT_EQ(compared, 2 * int(run.joint_names.size()));
  EXPECT_EQ(worst_rad, 0.0);
}

TEST(ScenarioRunner, SameSeedSameNumbers) {
  const test::TestDir dir("runner_determinism");
  const Scenario scenario = load_scenario(dir.write("noisy.yaml", R"(
scene: scene.yaml
duration_s: 1.0
seed: 5
methods: [encoders_only, full_fusion]
motion:
  random: [{joints: [left_arm], amplitude_deg: 10}]
encoders: [{joints: [arms], offset_deg: 5, noise_deg: 0.05}]
camera: {latency_s: 0.04, jitter_s: 0.01, drop_probability: 0.1, noise_sigma0_m: 0.002,
         dropout_probability: 0.05}
)"));
  auto numbers = [&](long long seed) {
    RunOptions options;
    options.seed = seed;
    options.runs = 2;
    const ScenarioResult r = run_scenario(scenario, options);
    std::stringstream csv;
    write_timeseries_csv(csv, r);
    for (const MethodResult& m : r.method_results)
      csv << m.summary.all.translation_m.p50 << ' ' << m.summary.all.rotation_rad.p99 << '\n';
    return csv.str();
  };
  const std::string a = numbers(5), b = numbers(5), c = numbers(6);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

// run_trajectory (render --time) is the motion run k follows: the run's
// true angles stay within the servos' lag of its targets, far closer than
// to another run's.
constexpr char kRandomMotion[] = R"(
scene: scene.yaml
duration_s: 3.0
seed: 5
methods: [encoders_only]
motion:
  random: [{joints: [left_arm], amplitude_deg: 20, fade_in_s: 0.5}]
)";

TEST(ScenarioRunner, RunTrajectoryIsTheMotionTheRunFollows) {
  const test::TestDir dir("runner_trajectory");
  const Scenario scenario = load_scenario(dir.write("random.yaml", kRandomMotion));
  RunOptions options;
  options.runs = 2;
  const ScenarioResult r = run_scenario(scenario, options);
  const auto model = build_sim_model(scenario.scene);
  const auto mean_error = [&](const RunResult& run, const JointTrajectory& motion) {
    std::vector<double> target(model->joint_names.size());
    double sum = 0;
    int n = 0;
    for (const TruthSample& t : run.truth) {
      motion.position(t.time_s, target);
      for (std::size_t j = 0; j < r.joint_names.size(); ++j) {
        if (r.joint_names[j].rfind("left_arm", 0) != 0) continue;  // the moving joints
        sum += std::abs(t.angle_rad[j] - target[std::size_t(model->joint_index(r.joint_names[j]))]);
        ++n;
      }
    }
    return sum / n;
  };
  const JointTrajectory run0 = run_trajectory(scenario, *model, scenario.seed, 0);
  const JointTrajectory run1 = run_trajectory(scenario, *model, scenario.seed, 1);
  const double own = mean_error(r.runs[0], run0), other = mean_error(r.runs[0], run1);
  std::printf("mean |true - target|: own motion %.4f rad, run 1's %.4f rad\n", own, other);
  EXPECT_LT(own, 0.05);  // the servos lag their targets by about a degree
  EXPECT_LT(4 * own, other);
  EXPECT_LT(mean_error(r.runs[1], run1), 0.05);
}

// The tracker's seed comes from the run's seed, and the configured
// particle_filter.seed picks another stream of it: setting it changes the
// particles' draws (it was once silently replaced), the default keeps them.
TEST(ScenarioRunner, TheTrackerSeedOfTheConfigurationChangesTheDraws) {
  const test::TestDir dir("runner_tracker_seed");
  const std::string yaml = R"(
scene: scene.yaml
duration_s: 0.5
seed: 5
methods: [full_fusion]
motion:
  random: [{joints: [left_arm], amplitude_deg: 10}]
encoders: [{joints: [arms], offset_deg: 5}]
)";
  auto numbers = [&](const std::string& name, const std::string& tracker) {
    const Scenario scenario = load_scenario(dir.write(name, yaml + tracker));
    RunOptions options;
    options.runs = 1;
    std::stringstream csv;
    write_timeseries_csv(csv, run_scenario(scenario, options));
    return csv.str();
  };
  const std::string plain = numbers("plain.yaml", "");
  const std::string one = numbers("one.yaml", "tracker_overrides: {particle_filter.seed: 1}\n");
  const std::string two = numbers("two.yaml", "tracker_overrides: {particle_filter.seed: 2}\n");
  EXPECT_EQ(plain, one);
  EXPECT_NE(plain, two);
}

// summary.json records what reproduces the run (the resolved scenario, the
// overrides, the tracker configuration, the seed, runs and methods, the
// version); running that record again gives the same time series byte for
// byte, even after the scenario file has changed.
TEST(ScenarioRunner, RerunFromTheSummaryGivesTheSameTimeseries) {
  const test::TestDir dir("runner_rerun");
  const fs::path file = dir.write("rerun.yaml", R"(
scene: scene.yaml
duration_s: 5
seed: 5
methods: [encoders_only]
motion:
  random: [{joints: [left_arm], amplitude_deg: 10}]
encoders: [{joints: [arms], offset_deg: 5, noise_deg: 0.05}]
camera: {latency_s: 0.04, jitter_s: 0.01, drop_probability: 0.1, noise_sigma0_m: 0.002}
)");
  const std::vector<std::string> overrides = {"duration_s=0.6",
                                              "tracker_overrides.particle_filter.particles=12"};
  const Scenario scenario = load_scenario(file, overrides);
  RunOptions options;
  options.seed = 8;
  options.methods = {"full_fusion"};
  const ScenarioResult first = run_scenario(scenario, options);
  write_run_outputs(dir.path() / "first", first);
  std::stringstream first_csv;
  write_timeseries_csv(first_csv, first);

  dir.write("rerun.yaml", "scene: nowhere.yaml\n");  // the file changes: the record does not
  const RunRecipe recipe = read_run_recipe(dir.path() / "first" / "summary.json");
  EXPECT_EQ(recipe.version, ARTTRACK_VERSION);
  EXPECT_EQ(recipe.overrides, overrides);
  EXPECT_EQ(recipe.seed, 8u);
  EXPECT_EQ(recipe.runs, 1);
  EXPECT_EQ(recipe.methods, std::vector<std::string>{"full_fusion"});
  EXPECT_NE(recipe.tracker_yaml.find("particles: 12"), std::string::npos);
  const Scenario again = scenario_from_recipe(recipe, "summary.json");
  EXPECT_EQ(again.tracker.particle_filter.num_particles, 12);
  EXPECT_EQ(again.duration_s, 0.6);
  RunOptions again_options;
  again_options.seed = (long long)recipe.seed;
  again_options.runs = recipe.runs;
  again_options.methods = recipe.methods;
  const ScenarioResult second = run_scenario(again, again_options);
  std::stringstream second_csv;
  write_timeseries_csv(second_csv, second);
  EXPECT_EQ(first_csv.str(), second_csv.str());
  EXPECT_EQ(summary_json(second).substr(summary_json(second).find("\"reproduce\"")),
            summary_json(first).substr(summary_json(first).find("\"reproduce\"")));

  // A summary without the record is an error naming the file.
  const fs::path old = dir.write("old.json", "{\"scenario\": \"x\"}");
  EXPECT_NE(test_support::error_of([&] { read_run_recipe(old); }).find("old.json"),
            std::string::npos);
}

TEST(ScenarioRunner, RunSeedsAreDistinctAndJsonSafe) {
  EXPECT_EQ(run_seed(1, 0), run_seed(1, 0));
  EXPECT_NE(run_seed(1, 0), run_seed(1, 1));
  EXPECT_NE(run_seed(1, 0), run_seed(2, 0));
  for (int k = 0; k < 100; ++k) EXPECT_LT(run_seed(7, k), std::uint64_t(1) << 53);
}

}  // namespace
}  // namespace arttrack::sim
