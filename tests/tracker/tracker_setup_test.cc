// TrackerSetup (tracker/internal): the wiring Tracker's constructor does
// once, from the model, the configuration and the encoders' order.
#include "arttrack/tracker/internal/tracker_setup.h"
#include "arttrack/tracker/tracker.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "../error_of.h"
#include "planar_arm.h"

namespace arttrack {
namespace {

using namespace test_support;  // the planar arm (planar_arm.h)

TEST(TrackerSetup, MapsTheEncodersOrderToDofsAndNamesTheEndEffectors) {
  const auto model = arm_model();
  const TrackerSetup s(model, small_config(TrackingMethod::kFullFusion), {"elbow", "shoulder"});
  EXPECT_EQ(s.n, 8);
  EXPECT_EQ(s.n_phys, 2);
  EXPECT_TRUE(s.use_encoders);
  EXPECT_TRUE(s.use_images);
  EXPECT_EQ(s.encoder_dof,
            (std::vector<int>{model->joint_index("elbow"), model->joint_index("shoulder")}));
  EXPECT_EQ(s.ee_links, std::vector<int>{model->link_index("tool")});
  EXPECT_EQ(s.filter_model->num_joints(), 8);
  EXPECT_EQ(s.filter_model->num_encoder_joints(), 2);
}

// Only full fusion estimates biases, per joint as configured; vision only's
// angles diffuse at its own rate; encoders only draws no image.
TEST(TrackerSetup, TheMethodDecidesWhatIsEstimated) {
  const auto model = arm_model();
  const int shoulder = model->joint_index("shoulder"), elbow = model->joint_index("elbow");
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  JointFilterParams exact = c.joint_defaults;
  exact.estimate_bias = false;
  c.joint_overrides["shoulder"] = JointFilterOverride::all_of(exact);
  const TrackerSetup fusion(model, c, {"shoulder", "elbow"});
  EXPECT_EQ(fusion.bias_estimated[std::size_t(shoulder)], 0);
  EXPECT_EQ(fusion.bias_estimated[std::size_t(elbow)], 1);
  EXPECT_EQ(fusion.filter_model->bias_rate_var()[shoulder], 0.0);
  EXPECT_GT(fusion.filter_model->bias_rate_var()[elbow], 0.0);

  c.method = TrackingMethod::kCameraOffsetOnly;
  const TrackerSetup offset(model, c, {"shoulder", "elbow"});
  EXPECT_EQ(offset.bias_estimated, std::vector<char>(2, 0));

  c.method = TrackingMethod::kVisionOnly;
  c.vision_only_angle_diffusion_rad_per_sqrt_s = 0.7;
  const TrackerSetup vision(model, c, {});
  EXPECT_FALSE(vision.use_encoders);
  EXPECT_TRUE(vision.encoder_dof.empty());
  EXPECT_EQ(vision.bias_estimated, std::vector<char>(2, 0));
  EXPECT_DOUBLE_EQ(vision.filter_model->angle_rate_var()[elbow], 0.7 * 0.7);

  c.method = TrackingMethod::kEncodersOnly;
  EXPECT_FALSE(TrackerSetup(model, c, {"shoulder", "elbow"}).use_images);
}

TEST(TrackerSetup, RefusesAnEncoderOrderThatIsNotEveryPhysicalJointOnce) {
  const auto model = arm_model();
  const TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  EXPECT_EQ(error_of([&] {
              TrackerSetup(model, c, {"shoulder", "shoulder"});
            }),
            "encoder joint 'shoulder' is listed twice");
  EXPECT_EQ(error_of([&] {
              TrackerSetup(model, c, {"shoulder", "camera_offset_x"});
            }),
            "encoder joint 'camera_offset_x' is a virtual camera joint");
  EXPECT_EQ(error_of([&] { TrackerSetup(model, c, {"shoulder"}); }),
            "no encoder reading for joint 'elbow' (every physical joint needs one, except for "
            "vision_only)");
}

// Full fusion samples at least min_evaluations per image over its blocks
// (the planar arm's 2 joints and 6 camera joints: 8 blocks); the other
// methods exactly the configured particles, without the bandwidth floor.
TEST(TrackerSetup, FullFusionSamplesAtLeastMinEvaluationsPerImage) {
  const auto model = arm_model();
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  c.particle_filter.bandwidth_factor = 1;
  const int blocks = int(sampling_blocks(*model, c).size());
  ASSERT_EQ(blocks, 8);
  EXPECT_EQ(particle_filter_params(c, blocks).num_particles, 40);  // min_evaluations 0
  c.min_evaluations = 400;
  EXPECT_EQ(particle_filter_params(c, blocks).num_particles, 50);
  c.min_evaluations = 401;
  EXPECT_EQ(particle_filter_params(c, blocks).num_particles, 51);  // rounded up
  c.min_evaluations = 320;
  EXPECT_EQ(particle_filter_params(c, blocks).num_particles, 40);  // never fewer than configured
  EXPECT_EQ(particle_filter_params(c, blocks).bandwidth_factor, 1);
  c.method = TrackingMethod::kVisionOnly;
  c.min_evaluations = 400;
  EXPECT_EQ(particle_filter_params(c, blocks).num_particles, 40);
  EXPECT_EQ(particle_filter_params(c, blocks).bandwidth_factor, 0);
}

// Full fusion samples camera_blocks_per_image of the 6 camera blocks per
// image; the other methods every block. A block of a physical joint with a
// camera joint is not a camera block.
TEST(TrackerSetup, FullFusionSamplesCameraBlocksPerImage) {
  const auto model = arm_model();
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  const std::vector<SamplingBlock> blocks = sampling_blocks(*model, c);
  ASSERT_EQ(blocks.size(), 8u);
  EXPECT_EQ(std::count_if(blocks.begin(), blocks.end(),
                          [&](const SamplingBlock& b) { return is_camera_block(b, *model); }),
            6);
  EXPECT_EQ(blocks_sampled_per_image(blocks, *model, c), 4);  // the default 2
  c.camera_blocks_per_image = 6;
  EXPECT_EQ(blocks_sampled_per_image(blocks, *model, c), 8);
  c.camera_blocks_per_image = 2;
  c.min_evaluations = 400;
  EXPECT_EQ(particle_filter_params(c, blocks_sampled_per_image(blocks, *model, c)).num_particles,
            100);
  c.method = TrackingMethod::kCameraOffsetOnly;
  EXPECT_EQ(blocks_sampled_per_image(sampling_blocks(*model, c), *model, c), 6);
  c.method = TrackingMethod::kFullFusion;
  c.blocks = {{"arm_and_x", {"shoulder", "camera_offset_x"}}, {"roll", {"camera_offset_roll"}}};
  const std::vector<SamplingBlock> custom = sampling_blocks(*model, c);
  EXPECT_FALSE(is_camera_block(custom[0], *model));
  EXPECT_TRUE(is_camera_block(custom[1], *model));
  c.camera_blocks_per_image = 1;
  EXPECT_EQ(blocks_sampled_per_image(custom, *model, c), 2);
}

}  // namespace
}  // namespace arttrack
