#include "arttrack/tracker/internal/unseen_joints.h"

#include <gtest/gtest.h>

#include <vector>

#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/units.h"
#include "planar_arm.h"

namespace arttrack {
namespace {

using arttrack::test_support::arm_model;
using arttrack::test_support::small_config;

// A camera that sees the arm standing up (shoulder 0) but nothing of it
// laid sideways (shoulder 1.5 rad): 20 degrees of view at a metre.
const CameraIntrinsics kNarrow = CameraIntrinsics::from_vertical_fov(64, 48, 20 * kRadPerDeg);

// What the camera sees behind the arm wherever it looks: a wall 3 m away.
// Every link the camera draws is seen (the wall is behind it).
DepthImage wall_behind(const CameraIntrinsics& camera) {
  return DepthImage(camera.width, camera.height, 3.0f);
}

JointBelief belief_at(const RobotModel& model, double shoulder, double elbow) {
  JointBelief b;
  const std::size_t n = std::size_t(model.num_joints());
  for (auto* v : {&b.mean_a, &b.mean_b, &b.var_a, &b.cov_ab, &b.var_b}) v->assign(n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    b.var_a[j] = 0.01;
    b.var_b[j] = 0.009;
    b.cov_ab[j] = -0.009;
  }
  b.mean_a[std::size_t(model.joint_index("shoulder"))] = shoulder;
  b.mean_a[std::size_t(model.joint_index("elbow"))] = elbow;
  b.mean_b[std::size_t(model.joint_index("shoulder"))] = 0.05;
  return b;
}

TEST(UnseenJointsTest, FindsTheJointsWhoseLinksTheCameraDoesNotDraw) {
  auto model = arm_model();
  const TrackerSetup setup(model, small_config(TrackingMethod::kFullFusion), {"shoulder", "elbow"});
  const int shoulder = model->joint_index("shoulder"), elbow = model->joint_index("elbow");
  UnseenJoints unseen(setup, {shoulder, elbow});
  ASSERT_TRUE(unseen.on());
  DepthRenderer renderer(*model, kNarrow);
  EXPECT_EQ(unseen.find(belief_at(*model, 0.0, 0.0), renderer, wall_behind(kNarrow)), 0);
  EXPECT_EQ(unseen.find(belief_at(*model, 1.5, 0.0), renderer, wall_behind(kNarrow)), 2);
  // The forearm bent back into view: both joints move it.
  EXPECT_EQ(unseen.find(belief_at(*model, 1.5, -2.0), renderer, wall_behind(kNarrow)), 0);
}

TEST(UnseenJointsTest, GivesAnUnseenJointItsPriorBackUnlessExplainedPixelsDependOnIt) {
  auto model = arm_model();
  const TrackerSetup setup(model, small_config(TrackingMethod::kFullFusion), {"shoulder", "elbow"});
  const int shoulder = model->joint_index("shoulder"), elbow = model->joint_index("elbow");
  UnseenJoints unseen(setup, {shoulder, elbow});
  DepthRenderer renderer(*model, kNarrow);
  const JointBelief prior = belief_at(*model, 1.5, 0.0);
  ASSERT_EQ(unseen.find(prior, renderer, wall_behind(kNarrow)), 2);
  // What a particle filter did to them: means moved, variances cut.
  JointBelief after = prior;
  for (int j : {shoulder, elbow}) {
    after.mean_a[std::size_t(j)] += 0.02;
    after.mean_b[std::size_t(j)] -= 0.02;
    after.var_a[std::size_t(j)] = 0.001;
  }
  // The elbow's mean now explains pixels: kept; the shoulder's back.
  EXPECT_EQ(unseen.keep_priors(std::vector<int>{0, 12}, after), 1);
  for (auto field : {&JointBelief::mean_a, &JointBelief::mean_b, &JointBelief::var_a,
                     &JointBelief::cov_ab, &JointBelief::var_b})
    EXPECT_EQ((after.*field)[std::size_t(shoulder)], (prior.*field)[std::size_t(shoulder)]);
  EXPECT_EQ(after.mean_a[std::size_t(elbow)], prior.mean_a[std::size_t(elbow)] + 0.02);
  EXPECT_EQ(after.var_a[std::size_t(elbow)], 0.001);
  // A joint found in view is never given its prior back.
  ASSERT_EQ(unseen.find(belief_at(*model, 0.0, 0.0), renderer, wall_behind(kNarrow)), 0);
  JointBelief seen = belief_at(*model, 0.1, 0.0);
  EXPECT_EQ(unseen.keep_priors(std::vector<int>{0, 0}, seen), 0);
  EXPECT_EQ(seen.mean_a[std::size_t(shoulder)], 0.1);
}

// unseen_below_pixels: a chain drawing fewer pixels than it counts as out of
// view, and keeps its prior unless as many explained pixels depend on it.
TEST(UnseenJointsTest, AChainDrawingFewerPixelsThanTheThresholdCountsAsUnseen) {
  auto model = arm_model();
  const int shoulder = model->joint_index("shoulder"), elbow = model->joint_index("elbow");
  DepthRenderer renderer(*model, kNarrow);
  const JointBelief standing = belief_at(*model, 0.0, 0.0);
  TrackerConfig config = small_config(TrackingMethod::kFullFusion);
  config.unseen_below_pixels = 1;  // only a chain wholly out of view
  EXPECT_EQ(UnseenJoints(TrackerSetup(model, config, {"shoulder", "elbow"}), {shoulder, elbow})
                .find(standing, renderer, wall_behind(kNarrow)),
            0);
  // More pixels than the whole view holds: the standing arm, which reaches
  // past the narrow view's edge, is "unseen"; the same arm wholly inside a
  // wide view is seen, however few its pixels.
  config.unseen_below_pixels = kNarrow.width * kNarrow.height + 1;
  UnseenJoints unseen(TrackerSetup(model, config, {"shoulder", "elbow"}), {shoulder, elbow});
  DepthRenderer wide(*model, CameraIntrinsics::from_vertical_fov(64, 48, 60 * kRadPerDeg));
  EXPECT_EQ(unseen.find(standing, wide, wall_behind(wide.camera())), 0);
  ASSERT_EQ(unseen.find(standing, renderer, wall_behind(kNarrow)), 2);
  JointBelief after = standing;
  for (int j : {shoulder, elbow}) after.mean_a[std::size_t(j)] += 0.02;
  // An explained pixel depends on the shoulder at the filter's mean: its
  // step is kept, however few; none on the elbow: its prior is back.
  EXPECT_EQ(unseen.keep_priors(std::vector<int>{1, 0}, after), 1);
  EXPECT_EQ(after.mean_a[std::size_t(shoulder)], 0.02);
  EXPECT_EQ(after.mean_a[std::size_t(elbow)], 0.0);
}

// A link behind a nearer surface (the image more than health.explained_m in
// front of it) or where the camera has no return is not seen either: the
// image says only where it is not.
TEST(UnseenJointsTest, ALinkBehindANearerSurfaceOrWithoutReturnsIsNotSeen) {
  auto model = arm_model();
  const int shoulder = model->joint_index("shoulder"), elbow = model->joint_index("elbow");
  TrackerConfig config = small_config(TrackingMethod::kFullFusion);
  config.unseen_below_pixels = 1;
  UnseenJoints unseen(TrackerSetup(model, config, {"shoulder", "elbow"}), {shoulder, elbow});
  DepthRenderer renderer(*model, kNarrow);
  const JointBelief standing = belief_at(*model, 0.0, 0.0);
  const DepthImage arm = test_support::render_truth(*model, 0.0, 0.0, kNarrow);
  ASSERT_GT(test_support::drawn_pixels(arm), 100);
  const auto nearer_by = [&](float d_m) {
    DepthImage image = wall_behind(kNarrow);
    for (std::size_t i = 0; i < arm.depth_m.size(); ++i)
      if (arm.depth_m[i] > 0) image.depth_m[i] = arm.depth_m[i] - d_m;
    return image;
  };
  // The arm where the camera sees it, within explained_m: seen.
  EXPECT_EQ(unseen.find(standing, renderer, nearer_by(0.5f * float(config.health.explained_m))), 0);
  // A surface 5 cm in front of the whole arm, or no return anywhere.
  EXPECT_EQ(unseen.find(standing, renderer, nearer_by(0.05f)), 2);
  EXPECT_EQ(unseen.find(standing, renderer, DepthImage(kNarrow.width, kNarrow.height, 0.f)), 2);
  // A panel in front of the forearm only: the elbow moves nothing the camera
  // sees; the shoulder moves the upper arm, which it sees.
  KinematicsState state(*model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model->num_joints());
  forward_kinematics(*model, q, state);
  LinkSet forearm(std::size_t(model->num_links()), false);
  forearm[std::size_t(model->link_index("lower"))] = true;
  DepthImage forearm_depth;
  renderer.render_links(state, forearm, forearm_depth);
  DepthImage panel = nearer_by(0.f);
  for (std::size_t i = 0; i < panel.depth_m.size(); ++i)
    if (forearm_depth.depth_m[i] > 0) panel.depth_m[i] = forearm_depth.depth_m[i] - 0.05f;
  ASSERT_EQ(unseen.find(standing, renderer, panel), 1);
  JointBelief after = standing;
  for (int j : {shoulder, elbow}) after.mean_a[std::size_t(j)] += 0.02;
  EXPECT_EQ(unseen.keep_priors(std::vector<int>{0, 0}, after), 1);
  EXPECT_EQ(after.mean_a[std::size_t(shoulder)], 0.02);
  EXPECT_EQ(after.mean_a[std::size_t(elbow)], 0.0);
  // An image of another size than the camera's is an error, not a misread.
  EXPECT_THROW(unseen.find(standing, renderer, DepthImage(kNarrow.width / 2, kNarrow.height, 3.f)),
               InputError);
}

TEST(UnseenJointsTest, OffWithTheOptionOrOutsideFullFusion) {
  auto model = arm_model();
  TrackerConfig config = small_config(TrackingMethod::kFullFusion);
  config.keep_unseen_prior = false;
  EXPECT_FALSE(UnseenJoints(TrackerSetup(model, config, {"shoulder", "elbow"}), {0}).on());
  EXPECT_FALSE(UnseenJoints(TrackerSetup(model, small_config(TrackingMethod::kVisionOnly),
                                         {"shoulder", "elbow"}),
                            {0})
                   .on());
}

}  // namespace
}  // namespace arttrack
