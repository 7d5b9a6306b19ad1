#include "arttrack/tracker/tracker_config.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>
#include <limits>
#include <set>

#include "../error_of.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/worker_pool.h"
#include "arttrack/tracker/tracker_config_yaml.h"

namespace arttrack {
namespace {

using arttrack::test_support::tracker_config_error;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

TEST(TrackerConfigTest, ReadsGeometry) {
  const TrackerConfig c = tracker_config_from_yaml(load_yaml_string(
      "geometry: {max_error_px: 0.5, nearest_range_m: 0.6, open_parts_both_sides: true}\n",
      "t.yaml"));
  EXPECT_EQ(c.geometry.max_error_px, 0.5);
  EXPECT_EQ(c.geometry.nearest_range_m, 0.6);
  EXPECT_TRUE(c.geometry.open_parts_both_sides);
  EXPECT_FALSE(default_tracker_config().geometry.open_parts_both_sides);
}

TEST(TrackerConfigTest, CameraJointsAreTranslationThenRotation) {
  TrackerConfig c;
  c.camera_translation.initial_std = 0.01;
  c.camera_rotation.initial_std = 0.02;
  for (int k = 0; k < 6; ++k)
    EXPECT_EQ(c.camera_joint_params(k).initial_std, k < 3 ? 0.01 : 0.02) << k;
  EXPECT_THROW(c.camera_joint_params(-1), InputError);
  EXPECT_THROW(c.camera_joint_params(6), InputError);
}

TEST(TrackerConfigTest, ReadsWhetherTheFirstSearchMovesTheCamera) {
  for (const bool value : {false, true})
    EXPECT_EQ(
        tracker_config_from_yaml(load_yaml_string("acquisition: {search_camera: " +
                                                      std::string(value ? "true" : "false") + "}\n",
                                                  "t.yaml"))
            .acquisition.search_camera,
        value);
  EXPECT_NE(tracker_config_error("acquisition: {search_camera: maybe}\n")
                .find("acquisition.search_camera"),
            std::string::npos);
}

TEST(TrackerConfigTest, ReadsWhetherUnseenJointsKeepTheirPrior) {
  EXPECT_TRUE(default_tracker_config().keep_unseen_prior);
  for (const bool value : {false, true})
    EXPECT_EQ(
        tracker_config_from_yaml(load_yaml_string("particle_filter: {keep_unseen_prior: " +
                                                      std::string(value ? "true" : "false") + "}\n",
                                                  "t.yaml"))
            .keep_unseen_prior,
        value);
  EXPECT_NE(tracker_config_error("particle_filter: {keep_unseen_prior: 2}\n")
                .find("particle_filter.keep_unseen_prior"),
            std::string::npos);
}

TEST(TrackerConfigTest, ReadsHowFewPixelsCountAsOutOfView) {
  EXPECT_EQ(default_tracker_config().unseen_below_pixels, 30);
  EXPECT_EQ(tracker_config_from_yaml(
                load_yaml_string("particle_filter: {unseen_below_pixels: 12}\n", "t.yaml"))
                .unseen_below_pixels,
            12);
  for (const char* bad : {"0", "-3", "2.5"})
    EXPECT_NE(
        tracker_config_error("particle_filter: {unseen_below_pixels: " + std::string(bad) + "}\n")
            .find("particle_filter.unseen_below_pixels"),
        std::string::npos)
        << bad;
}

TEST(TrackerConfigTest, ReadsInputChecks) {
  const TrackerConfig c = tracker_config_from_yaml(load_yaml_string(
      "input_checks: {joint_limit_margin_deg: 10, max_image_clock_offset_s: 2}\n", "t.yaml"));
  EXPECT_NEAR(c.joint_limit_margin_rad, 10 * M_PI / 180, 1e-12);
  EXPECT_EQ(c.max_image_clock_offset_s, 2);
  for (const auto& [bad, key] : std::vector<std::pair<std::string, std::string>>{
           {"{joint_limit_margin_deg: -1}", "input_checks.joint_limit_margin_deg"},
           {"{max_image_clock_offset_s: 0}", "input_checks.max_image_clock_offset_s"}})
    EXPECT_NE(tracker_config_error("input_checks: " + bad + "\n").find(key), std::string::npos)
        << bad;
}

TEST(TrackerConfigTest, ReadsDegreesAndPerJointOverrides) {
  const TrackerConfig c = tracker_config_from_yaml(load_yaml_string(
      "method: camera_offset_only\n"
      "joints: {defaults: {encoder_noise_deg: 0.1}, per_joint: {elbow: {estimate_bias: false}}}\n"
      "particle_filter: {particles: 50, blocks: [{name: arm, joints: [shoulder, elbow]}]}\n",
      "t.yaml"));
  EXPECT_EQ(c.method, TrackingMethod::kCameraOffsetOnly);
  EXPECT_NEAR(c.joint_defaults.encoder_noise_rad, 0.1 * M_PI / 180, 1e-12);
  ASSERT_EQ(c.joint_overrides.count("elbow"), 1u);
  EXPECT_EQ(c.joint_overrides.at("elbow").estimate_bias, false);
  // An override holds what it gives: the rest, and its units, come from its
  // joint's defaults (joint_filter_params, tracker.h).
  EXPECT_FALSE(c.joint_overrides.at("elbow").encoder_noise);
  EXPECT_FALSE(c.joint_overrides.at("elbow").linear);
  EXPECT_EQ(c.particle_filter.num_particles, 50);
  ASSERT_EQ(c.blocks.size(), 1u);
  EXPECT_EQ(c.blocks[0].joints.size(), 2u);
}

TEST(TrackerConfigTest, ReadsTheOccluderModel) {
  const auto model = [](const std::string& name) {
    return tracker_config_from_yaml(
               load_yaml_string("depth_model: {occluder_model: " + name + "}\n", "t.yaml"))
        .depth_model.occluder_model;
  };
  EXPECT_EQ(model("truncated"), OccluderModel::kTruncated);
  EXPECT_EQ(model("independent"), OccluderModel::kIndependent);
}

TEST(TrackerConfigTest, BadKeysAndValuesAreNamed) {
  // Each file and what its error says: the key, or why.
  for (const auto& [yaml, part] :
       {std::pair{"methd: full_fusion\n", "'methd'"},
        {"method: fusion\n", "not one of"},
        {"depth_model: {occlusion_prior: 1.5}\n", "depth_model.occlusion_prior"},
        {"joints: {defaults: {bias_decay_per_s: 1.0}}\n", "bias_decay_per_s"},
        {"particle_filter: {particles: many}\n", "particle_filter.particles"},
        {"depth_model: {occluder_model: exponential}\n", "depth_model.occluder_model"},
        {"joints: {per_joint: {elbow: {noise: 1}}}\n", "joints.per_joint.elbow.noise"},
        // A prismatic joint's keys are in metres, a revolute one's in degrees.
        {"joints: {per_joint: {finger: {encoder_noise_m: 1e-4, angle_diffusion_deg_per_sqrt_s: "
         "1}}}\n",
         "joints.per_joint.finger.encoder_noise_m"},
        {"joints: {prismatic_defaults: {encoder_noise_deg: 0.1}}\n",
         "joints.prismatic_defaults.encoder_noise_deg"},
        {"joints: {prismatic_defaults: {encoder_noise_m: 2}}\n",
         "joints.prismatic_defaults.encoder_noise_m"},
        {"joints: {per_joint: {finger: {position_diffusion_m_per_sqrt_s: -1}}}\n",
         "joints.per_joint.finger.position_diffusion_m_per_sqrt_s"},
        // The keys of the abandoned-pixel check, the searches and the discount.
        {"acquisition: {searches: 0}\n", "acquisition.searches"},
        {"acquisition: {searches: 101}\n", "acquisition.searches"},
        {"health: {lost_abandoned_fraction: 1.5}\n", "health.lost_abandoned_fraction"},
        {"health: {lost_abandoned_fraction: -0.1}\n", "health.lost_abandoned_fraction"},
        {"uncertainty: {discount_correlated_residuals: often}\n",
         "uncertainty.discount_correlated_residuals"},
        {"uncertainty: {model_error_learned_shifts: maybe}\n",
         "uncertainty.model_error_learned_shifts"},
        {"uncertainty: {pixel_noise_after_fit: 1.5}\n", "uncertainty.pixel_noise_after_fit"},
        {"uncertainty: {model_error_unpinned_scale_on_learned: 2}\n",
         "uncertainty.model_error_unpinned_scale_on_learned"}})
    EXPECT_NE(tracker_config_error(yaml).find(part), std::string::npos) << yaml;
}

// The render section that chose a coarser tessellation for the hypotheses
// is gone (the tracker draws cylinders and spheres exactly): a file that
// still has it is told so, not silently ignored.
TEST(TrackerConfigTest, TheRemovedRenderSectionIsAnError) {
  const std::string error = tracker_config_error("render: {cylinder_segments: 16}\n");
  EXPECT_NE(error.find("render"), std::string::npos) << error;
  EXPECT_NE(error.find("not a known key"), std::string::npos) << error;
}

TEST(TrackerConfigTest, ThreadsHaveTheWorkerPoolsBound) {
  const std::string above = tracker_config_error(
      "particle_filter: {threads: " + std::to_string(kMaxWorkerThreads + 1) + "}\n");
  EXPECT_NE(above.find("particle_filter.threads"), std::string::npos) << above;
  EXPECT_EQ(tracker_config_error("particle_filter: {threads: " + std::to_string(kMaxWorkerThreads) +
                                 "}\n"),
            "");
  // Set in code, past the file reader: validate() holds the same bound.
  TrackerConfig config;
  config.threads = kMaxWorkerThreads + 1;
  const std::string code = test_support::error_of([&] { config.validate("c"); });
  EXPECT_NE(code.find("particle_filter.threads"), std::string::npos) << code;
}

// One row of the range table: `key` (as the YAML writes it) at `inside` is
// accepted, at `outside` rejected with a message naming the key; `also`: an
// override the row needs (another key the range depends on), or "".
struct RangeRow {
  std::string key;
  std::string inside;
  std::string outside;  // "" when no value lies past this end (infinity)
  std::string also = "";
};

const std::string kMaxThreads = std::to_string(kMaxWorkerThreads);

// Each key at both ends of its range (TrackerConfig::validate), in the YAML's
// units: degrees for _deg keys. An open end is tested with a value just
// inside it.
const std::vector<RangeRow> kRangeRows = {
    {"joints.defaults.encoder_noise_deg", "90", "90.0001"},
    {"joints.defaults.encoder_noise_deg", "1e-9", "0"},
    {"joints.defaults.angle_diffusion_deg_per_sqrt_s", "0", "-1e-9"},
    {"joints.defaults.angle_diffusion_deg_per_sqrt_s", "100000", "100001"},
    {"joints.defaults.bias_diffusion_deg_per_sqrt_s", "1e-9", "0"},
    {"joints.defaults.bias_diffusion_deg_per_sqrt_s", "100000", "100001"},
    {"joints.defaults.bias_decay_per_s", "1e-9", "0"},
    {"joints.defaults.bias_decay_per_s", "0.999999", "1"},
    {"joints.prismatic_defaults.encoder_noise_m", "1", "1.0001"},
    {"joints.prismatic_defaults.encoder_noise_m", "1e-12", "0"},
    {"joints.prismatic_defaults.position_diffusion_m_per_sqrt_s", "0", "-1e-9"},
    {"joints.prismatic_defaults.position_diffusion_m_per_sqrt_s", "1000", "1001"},
    {"joints.prismatic_defaults.bias_diffusion_m_per_sqrt_s", "0", "-1e-9"},
    {"joints.prismatic_defaults.bias_diffusion_m_per_sqrt_s", "1e-9", "0",
     "joints.prismatic_defaults.estimate_bias=true"},
    {"joints.prismatic_defaults.bias_diffusion_m_per_sqrt_s", "1000", "1001"},
    {"joints.prismatic_defaults.bias_decay_per_s", "1e-9", "0"},
    {"joints.prismatic_defaults.bias_decay_per_s", "0.999999", "1"},
    {"joints.per_joint.l_elbow.encoder_noise_deg", "90", "91"},
    {"joints.per_joint.l_elbow.bias_diffusion_deg_per_sqrt_s", "1e-6", "0"},
    {"joints.per_joint.l_elbow.bias_decay_per_s", "0.5", "1"},
    {"encoder_smoothing.rate_diffusion_deg_per_s_per_sqrt_s", "1e-6", "0"},
    {"encoder_smoothing.rate_diffusion_deg_per_s_per_sqrt_s", "1e5", "1.01e5"},
    {"camera_offset.translation_diffusion_m_per_sqrt_s", "0", "-0.001"},
    {"camera_offset.translation_diffusion_m_per_sqrt_s", "10", "10.001"},
    {"camera_offset.translation_initial_std_m", "1e-9", "0"},
    {"camera_offset.translation_initial_std_m", "10", "10.001"},
    {"camera_offset.rotation_diffusion_deg_per_sqrt_s", "0", "-1"},
    {"camera_offset.rotation_diffusion_deg_per_sqrt_s", "10000", "10001"},
    {"camera_offset.rotation_initial_std_deg", "1e-9", "0"},
    {"camera_offset.rotation_initial_std_deg", "180", "181"},
    {"camera_offset.translation_diffusion_m_per_sqrt_rad", "0", "-0.001"},
    {"camera_offset.translation_diffusion_m_per_sqrt_rad", "10", "10.001"},
    {"camera_offset.rotation_diffusion_deg_per_sqrt_rad", "0", "-1"},
    {"camera_offset.rotation_diffusion_deg_per_sqrt_rad", "10000", "10001"},
    {"vision_only.angle_diffusion_deg_per_sqrt_s", "0", "-1"},
    {"vision_only.angle_diffusion_deg_per_sqrt_s", "100000", "100001"},
    {"vision_only.initial_std_deg", "0", "-1"},
    {"vision_only.initial_std_deg", "180", "181"},
    {"depth_model.outlier_weight", "1e-9", "1e-10"},
    {"depth_model.outlier_weight", "1", "1.01"},
    {"depth_model.noise_std_m", "1e-6", "1e-7"},
    {"depth_model.noise_std_m", "0.5", "0.51", "acquisition.coarse_noise_std_m=0.5"},
    {"depth_model.noise_quadratic_per_m", "0", "-0.1"},
    {"depth_model.noise_quadratic_per_m", "1", "1.1", "depth_model.max_range_m=0.5"},
    {"depth_model.max_range_m", "0.1", "0.09"},
    {"depth_model.max_range_m", "100", "101"},
    {"depth_model.occluder_decay_per_m", "1e-3", "9e-4"},
    {"depth_model.occluder_decay_per_m", "100", "101", "acquisition.passes=1"},
    {"depth_model.occlusion_prior", "0", "-0.1"},
    {"depth_model.occlusion_prior", "1", "1.1"},
    {"depth_model.width", "4", "3"},
    {"depth_model.width", "4096", "4097"},
    {"depth_model.height", "3", "2"},
    {"depth_model.height", "4096", "4097"},
    {"particle_filter.particles", "1", "0"},
    {"particle_filter.particles", "1000000", "1000001"},
    {"particle_filter.max_kl_divergence", "0", "-0.1"},
    {"geometry.max_error_px", "0", "-0.1"},
    {"geometry.max_error_px", "4", "4.1"},
    {"geometry.nearest_range_m", "0.01", "0.009"},
    {"geometry.nearest_range_m", "100", "101"},
    {"geometry.coarser_levels", "0", "-1"},
    {"geometry.coarser_levels", "8", "9"},
    {"particle_filter.max_kl_divergence", ".inf", ""},
    {"particle_filter.proposal_scale", "1e-6", "1e-7"},
    {"particle_filter.proposal_scale", "1e6", "1.1e6"},
    {"particle_filter.no_evidence_nats", "0", "-1e-9"},
    {"particle_filter.no_evidence_nats", ".inf", ""},
    {"particle_filter.bandwidth_factor", "0", "-0.1"},
    {"particle_filter.bandwidth_factor", "10", "10.1"},
    {"particle_filter.block_moments_below_nats", "0", "-0.1"},
    {"particle_filter.block_moments_below_nats", ".inf", ""},
    {"particle_filter.likelihood_exponent", "1e-3", "9e-4"},
    {"particle_filter.likelihood_exponent", "1", "1.01"},
    {"particle_filter.threads", "0", "-1"},
    {"particle_filter.min_evaluations", "0", "-1"},
    {"particle_filter.min_evaluations", "1000000", "1000001"},
    {"particle_filter.camera_blocks_per_image", "1", "0"},
    {"particle_filter.camera_blocks_per_image", "6", "7"},
    {"particle_filter.unseen_below_pixels", "1", "0"},
    {"particle_filter.unseen_below_pixels", "1000000", "1000001"},
    {"particle_filter.threads", kMaxThreads, std::to_string(kMaxWorkerThreads + 1)},
    {"uncertainty.image_information_scale", "1e-6", "1e-7"},
    {"uncertainty.image_information_scale", "1", "1.1"},
    {"uncertainty.model_error_time_constant_s", "1e-3", "0"},
    {"uncertainty.model_error_time_constant_s", "1e4", "2e4"},
    {"uncertainty.model_error_min_std_m", "0", "-1e-3"},
    {"uncertainty.model_error_min_std_m", "0.1", "0.2"},
    {"uncertainty.model_error_unpinned_scale", "1", "0.9"},
    {"uncertainty.model_error_unpinned_scale", "10", "11"},
    {"uncertainty.model_error_learned_time_constant_s", "1e-3", "0"},
    {"uncertainty.model_error_learned_time_constant_s", "1e4", "2e4"},
    {"uncertainty.model_error_learned_max_std_m", "1e-6", "0"},
    {"uncertainty.model_error_learned_max_std_m", "0.1", "0.2"},
    {"uncertainty.link_length_std_m", "0", "-1e-3"},
    {"uncertainty.link_length_std_m", "0.1", "0.2"},
    {"uncertainty.depth_scale_std", "0", "-1e-3"},
    {"uncertainty.depth_scale_std", "0.1", "0.2"},
    {"uncertainty.mean_lag_scale", "0", "-1"},
    {"uncertainty.mean_lag_scale", "100", "101"},
    {"uncertainty.mean_lag_time_constant_s", "0.5", "0.4"},
    {"uncertainty.mean_lag_time_constant_s", "1e4", "2e4"},
    {"refinement.min_pixels", "1", "0"},
    {"refinement.min_pixels", "10000000", "10000001"},
    {"refinement.widen_beyond_sigma", "0", "-0.5"},
    {"refinement.widen_beyond_sigma", "100", "101"},
    {"refinement.unseen_information_ratio", "0", "-0.01"},
    {"refinement.unseen_information_ratio", "1", "1.5"},
    {"end_effector_fit.time_constant_s", "0.001", "0.0009"},
    {"end_effector_fit.time_constant_s", "10000", "10001"},
    {"end_effector_fit.max_std_m", "0.000001", "0"},
    {"end_effector_fit.max_std_m", "1", "1.1"},
    {"end_effector_fit.resolution_factor", "1", "0"},
    {"end_effector_fit.resolution_factor", "8", "9"},
    {"end_effector_fit.axis_search_range_m", "0", "-0.001"},
    {"end_effector_fit.axis_search_range_m", "0.05", "0.051"},
    {"acquisition.passes", "1", "0"},
    {"acquisition.passes", "10", "11"},
    {"acquisition.coarse_noise_std_m", "0.003", "0.0029"},  // depth_model.noise_std_m
    {"acquisition.coarse_noise_std_m", "0.5", "0.51"},
    {"acquisition.proposal_shrink", "0.05", "0.049"},
    {"acquisition.proposal_shrink", "1", "1.01"},
    {"acquisition.period_s", "0", "-1"},
    {"acquisition.period_s", "1e6", "1.1e6"},
    {"acquisition.bias_std_deg", "0.1", "0.09"},
    {"acquisition.bias_std_deg", "180", "181"},
    {"acquisition.accept_margin_nats", "0", "-1"},
    {"acquisition.accept_margin_nats", "1e6", "1.1e6"},
    {"acquisition.searches", "1", "0"},
    {"acquisition.searches", "100", "101"},
    {"health.explained_m", "1e-4", "9e-5"},
    {"health.explained_m", "1", "1.1"},
    {"health.contradicted_m", "1e-4", "9e-5"},
    {"health.contradicted_m", "1", "1.1"},
    {"health.lost_contradicted_fraction", "0", "-0.1"},
    {"health.lost_contradicted_fraction", "1", "1.1"},
    {"health.lost_abandoned_fraction", "0", "-0.1"},
    {"health.lost_abandoned_fraction", "1", "1.1"},
    {"health.unconfirmed_explained_fraction", "0", "-0.1"},
    {"health.unconfirmed_explained_fraction", "1", "1.1"},
    {"health.occluder_gap_m", "1e-3", "9e-4"},
    {"health.occluder_gap_m", "10", "10.1"},
    {"health.lost_after_images", "1", "0"},
    {"health.lost_after_images", "1000000", "1000001"},
    {"health.min_pixels", "1", "0"},
    {"health.min_pixels", "10000000", "10000001"},
    {"timing.camera_delay_s", "0", "-0.1"},
    {"timing.camera_delay_s", "10", "10.1"},
    {"timing.buffer_capacity", "2", "1"},
    {"timing.buffer_capacity", "10000000", "10000001"},
    {"timing.max_pending_images", "1", "0"},
    {"timing.max_pending_images", "1000", "1001"},
    {"input_checks.joint_limit_margin_deg", "0", "-1"},
    {"input_checks.joint_limit_margin_deg", "3600", "3601"},
    {"input_checks.max_image_clock_offset_s", "1e-3", "9e-4"},
    {"input_checks.max_image_clock_offset_s", "1e6", "1.1e6"},
};

// The message of reading the built-in defaults with `overrides` applied
// ("" when they are accepted).
std::string defaults_error(const std::vector<std::string>& overrides) {
  return test_support::error_of([&] {
    YamlDocument doc = default_tracker_document();
    for (const std::string& o : overrides)
      if (!o.empty()) apply_override(doc, o);
    tracker_config_from_yaml(doc);
  });
}

TEST(TrackerConfigTest, EveryKeyIsAcceptedAtItsBoundsAndRejectedPastThem) {
  for (const RangeRow& row : kRangeRows) {
    EXPECT_EQ(defaults_error({row.key + "=" + row.inside, row.also}), "")
        << row.key << " = " << row.inside;
    if (row.outside.empty()) continue;
    const std::string e = defaults_error({row.key + "=" + row.outside, row.also});
    EXPECT_NE(e.find(kDefaultTrackerConfigName), std::string::npos) << e;
    EXPECT_NE(e.find("key '" + row.key + "' = "), std::string::npos) << row.key << ": " << e;
    EXPECT_NE(e.find(" is out of range "), std::string::npos) << row.key << ": " << e;
  }
}

// Every number of the shipped file has rows (a new key cannot go unchecked).
void number_keys(const YAML::Node& node, const std::string& path, std::set<std::string>& keys) {
  if (node.IsMap()) {
    for (const auto& kv : node)
      number_keys(kv.second, (path.empty() ? "" : path + ".") + kv.first.Scalar(), keys);
  } else if (node.IsScalar()) {
    double v;
    if (YAML::convert<double>::decode(node, v)) keys.insert(path);
  }
}

TEST(TrackerConfigTest, TheRangeTableCoversEveryNumberOfTheDefaults) {
  std::set<std::string> keys;
  number_keys(default_tracker_document().root, "", keys);
  keys.erase("particle_filter.seed");  // any value
  ASSERT_GT(keys.size(), 40u);
  std::set<std::string> rows;
  for (const RangeRow& row : kRangeRows) rows.insert(row.key);
  for (const std::string& key : keys) EXPECT_TRUE(rows.count(key)) << key << " has no range row";
}

// The message gives the value and the range in the YAML's units.
TEST(TrackerConfigTest, RangesAreGivenInTheUnitsOfTheKey) {
  EXPECT_NE(defaults_error({"joints.per_joint.l_elbow.encoder_noise_deg=95"})
                .find("key 'joints.per_joint.l_elbow.encoder_noise_deg' = 95 is out of range "
                      "(0, 90]"),
            std::string::npos);
  EXPECT_NE(defaults_error({"depth_model.max_range_m=200"})
                .find("key 'depth_model.max_range_m' = 200 is out of range [0.1, 100]"),
            std::string::npos);
  EXPECT_NE(defaults_error({"acquisition.coarse_noise_std_m=0.002"})
                .find("= 0.002 is out of range [0.003 (depth_model.noise_std_m), 0.5]"),
            std::string::npos);
  // Without a bias estimate its diffusion may be 0.
  EXPECT_EQ(defaults_error({"joints.per_joint.l_elbow={estimate_bias: false, "
                            "bias_diffusion_deg_per_sqrt_s: 0}"}),
            "");
  // The first search pass's depth model must be valid too.
  EXPECT_NE(defaults_error({"depth_model.occluder_decay_per_m=100"})
                .find("key 'acquisition.coarse_noise_std_m' = "),
            std::string::npos);
}

// The reader checks types only: numbers (not NaN), whole numbers for counts.
TEST(TrackerConfigTest, TheReaderChecksTypes) {
  for (const auto& [o, part] : std::vector<std::pair<std::string, std::string>>{
           {"particle_filter.particles=2.5",
            "key 'particle_filter.particles' = 2.5 is not a whole"},
           {"particle_filter.particles=1e12", "key 'particle_filter.particles' = 1e+12 is not a"},
           {"depth_model.max_range_m=.nan", "key 'depth_model.max_range_m' must be a number"},
           {"depth_model.max_range_m=far", "key 'depth_model.max_range_m' must be a number"},
           {"timing.camera_delay_s=.inf", "key 'timing.camera_delay_s' = inf is out of range"},
           {"particle_filter.block_moments_below_nats=some",
            "key 'particle_filter.block_moments_below_nats' must be a number"},
           {"geometry.open_parts_both_sides=maybe",
            "key 'geometry.open_parts_both_sides' has the wrong type"},
           {"encoder_noise.from_readings=maybe",
            "key 'encoder_noise.from_readings' has the wrong type"}})
    EXPECT_NE(defaults_error({o}).find(part), std::string::npos)
        << o << ": " << defaults_error({o});
}

// A configuration built in code gets the same checks, with the same keys.
TEST(TrackerConfigTest, ValidateRejectsABadStructNamingTheKey) {
  const std::vector<std::pair<std::function<void(TrackerConfig&)>, std::string>> cases = {
      {[](TrackerConfig& c) { c.joint_overrides["l_elbow"].bias_decay_per_s = 1; },
       "key 'joints.per_joint.l_elbow.bias_decay_per_s' = 1 is out of range (0, 1)"},
      {[](TrackerConfig& c) { c.joint_defaults.encoder_noise_rad = kInfinity; },
       "key 'joints.defaults.encoder_noise_deg' = inf"},
      {[](TrackerConfig& c) { c.camera_rotation.initial_std = 0; },
       "key 'camera_offset.rotation_initial_std_deg' = 0"},
      {[](TrackerConfig& c) { c.camera_translation.diffusion_per_sqrt_s = -1; },
       "key 'camera_offset.translation_diffusion_m_per_sqrt_s' = -1"},
      {[](TrackerConfig& c) { c.depth_model.max_range_m = 200; },
       "key 'depth_model.max_range_m' = 200 is out of range [0.1, 100]"},
      {[](TrackerConfig& c) { c.particle_filter.num_particles = 0; },
       "key 'particle_filter.particles' = 0"},
      {[](TrackerConfig& c) { c.particle_filter.no_evidence_nats = -1; },
       "key 'particle_filter.no_evidence_nats' = -1"},
      {[](TrackerConfig& c) { c.likelihood_exponent = 0; },
       "key 'particle_filter.likelihood_exponent' = 0"},
      {[](TrackerConfig& c) { c.camera_delay_s = std::nan(""); },
       "key 'timing.camera_delay_s' = nan"},
      {[](TrackerConfig& c) {
         c.blocks = {{"", {"a"}}};
       },
       "key 'particle_filter.blocks[0].name' is empty"},
      {[](TrackerConfig& c) { c.camera_frame = ""; }, "key 'camera_frame' is empty"},
  };
  for (const auto& [change, part] : cases) {
    TrackerConfig c;
    EXPECT_EQ(test_support::error_of([&] { c.validate("code"); }), "");
    change(c);
    const std::string e = test_support::error_of([&] { c.validate("code"); });
    EXPECT_EQ(e.rfind("code: ", 0), 0u) << e;
    EXPECT_NE(e.find(part), std::string::npos) << e;
  }
}

}  // namespace
}  // namespace arttrack
