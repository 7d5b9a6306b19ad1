#include "arttrack/tracker/tracker_config.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../error_of.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/tracker_config_yaml.h"

namespace arttrack {
namespace {

using arttrack::test_support::tracker_config_error;

// The shipped file documents every key with the in-code defaults.
TEST(TrackerConfigTest, DefaultFileEqualsTheBuiltInDefaults) {
  const TrackerConfig file =
      load_tracker_config(std::string(ARTTRACK_SOURCE_DIR) + "/tracker/config/default.yaml");
  const TrackerConfig code;
  EXPECT_EQ(file.method, code.method);
  EXPECT_EQ(file.end_effectors, code.end_effectors);
  EXPECT_NEAR(file.joint_defaults.encoder_noise_rad, code.joint_defaults.encoder_noise_rad, 1e-5);
  EXPECT_NEAR(file.joint_defaults.angle_diffusion_rad_per_sqrt_s,
              code.joint_defaults.angle_diffusion_rad_per_sqrt_s, 1e-3);
  EXPECT_NEAR(file.joint_defaults.bias_diffusion_rad_per_sqrt_s,
              code.joint_defaults.bias_diffusion_rad_per_sqrt_s, 1e-3);
  EXPECT_EQ(file.joint_defaults.bias_decay_per_s, code.joint_defaults.bias_decay_per_s);
  EXPECT_NEAR(file.camera_rotation.initial_std, code.camera_rotation.initial_std, 1e-3);
  EXPECT_NEAR(file.camera_rotation.diffusion_per_sqrt_s, code.camera_rotation.diffusion_per_sqrt_s,
              1e-4);
  EXPECT_EQ(file.camera_translation.initial_std, code.camera_translation.initial_std);
  EXPECT_EQ(file.depth_model.width, code.depth_model.width);
  EXPECT_EQ(file.depth_model.occlusion_prior, code.depth_model.occlusion_prior);
  EXPECT_EQ(file.depth_model.occluder_model, code.depth_model.occluder_model);
  // Robot-agnostic: no per-joint overrides (the dual-arm robot's are in
  // its scene, models/scene_default.yaml).
  EXPECT_TRUE(code.joint_overrides.empty());
  EXPECT_TRUE(file.joint_overrides.empty());
  EXPECT_EQ(file.particle_filter.num_particles, code.particle_filter.num_particles);
  EXPECT_EQ(file.buffer_capacity, code.buffer_capacity);
  EXPECT_EQ(file.asynchronous, code.asynchronous);
  EXPECT_NEAR(file.joint_limit_margin_rad, code.joint_limit_margin_rad, 1e-12);
  EXPECT_EQ(file.max_image_clock_offset_s, code.max_image_clock_offset_s);
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
  EXPECT_FALSE(c.joint_overrides.at("elbow").estimate_bias);
  // An override starts from the (file's) defaults.
  EXPECT_NEAR(c.joint_overrides.at("elbow").encoder_noise_rad, 0.1 * M_PI / 180, 1e-12);
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
  EXPECT_NE(tracker_config_error("methd: full_fusion\n").find("'methd'"), std::string::npos);
  EXPECT_NE(tracker_config_error("method: fusion\n").find("not one of"), std::string::npos);
  EXPECT_NE(tracker_config_error("depth_model: {occlusion_prior: 1.5}\n")
                .find("depth_model.occlusion_prior"),
            std::string::npos);
  EXPECT_NE(tracker_config_error("joints: {defaults: {bias_decay_per_s: 1.0}}\n")
                .find("bias_decay_per_s"),
            std::string::npos);
  EXPECT_NE(tracker_config_error("particle_filter: {particles: many}\n")
                .find("particle_filter.particles"),
            std::string::npos);
  EXPECT_NE(tracker_config_error("depth_model: {occluder_model: exponential}\n")
                .find("depth_model.occluder_model"),
            std::string::npos);
  EXPECT_NE(tracker_config_error("joints: {per_joint: {elbow: {noise: 1}}}\n")
                .find("joints.per_joint.elbow.noise"),
            std::string::npos);
  // The keys of the abandoned-pixel check, the searches and the discount.
  for (const auto& [yaml, key] :
       {std::pair{"acquisition: {searches: 0}\n", "acquisition.searches"},
        {"acquisition: {searches: 101}\n", "acquisition.searches"},
        {"health: {lost_abandoned_fraction: 1.5}\n", "health.lost_abandoned_fraction"},
        {"health: {lost_abandoned_fraction: -0.1}\n", "health.lost_abandoned_fraction"},
        {"uncertainty: {discount_correlated_residuals: often}\n",
         "uncertainty.discount_correlated_residuals"}})
    EXPECT_NE(tracker_config_error(yaml).find(key), std::string::npos) << yaml;
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

}  // namespace
}  // namespace arttrack
