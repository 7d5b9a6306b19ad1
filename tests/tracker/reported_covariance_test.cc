// ReportedCovariance (tracker/internal): the states of the covariance the
// tracker reports, and an image's update of it.
#include "arttrack/tracker/internal/reported_covariance.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "planar_arm.h"

namespace arttrack {
namespace {

using namespace test_support;  // the planar arm (planar_arm.h)
using Kind = PosteriorCovariance::Kind;

// Full fusion: a bias per encoder joint whose bias is estimated, an angle
// per camera joint; vision only: angles throughout.
TEST(ReportedCovariance, StatesAreTheSampledDofsBiasesForEncoderJoints) {
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  JointFilterParams exact = c.joint_defaults;
  exact.estimate_bias = false;
  c.joint_overrides["elbow"] = JointFilterOverride::all_of(exact);
  const TrackerSetup fusion(arm_model(), c, {"shoulder", "elbow"});
  const ReportedCovarianceSetup s(fusion, sampling_blocks(*fusion.model, c));
  const int shoulder = fusion.model->joint_index("shoulder");
  ASSERT_EQ(s.states.size(), 7u);  // the shoulder's bias, the camera's six angles
  EXPECT_EQ(s.states[0].dof, shoulder);
  EXPECT_EQ(s.states[0].kind, Kind::kBias);
  EXPECT_EQ(s.states[0].rate_var, fusion.filter_model->bias_rate_var()[shoulder]);
  EXPECT_EQ(s.states[0].decay_per_s, fusion.filter_model->bias_decay_rate_per_s()[shoulder]);
  for (std::size_t i = 1; i < 7; ++i) {
    EXPECT_EQ(s.states[i].kind, Kind::kAngle);
    EXPECT_EQ(s.states[i].dof, fusion.n_phys + int(i) - 1);
  }
  EXPECT_EQ(s.dofs.size(), s.states.size());
  // Per link with geometry: its shift's three axes, then its bulge.
  const int links = int(fusion.model->links_with_geometry().size());
  EXPECT_EQ(s.num_consider, 4 * links);
  EXPECT_EQ(s.first_bulge, 3 * links);
  EXPECT_EQ(s.num_bulges, links);

  c.method = TrackingMethod::kVisionOnly;
  c.model_error = false;
  const TrackerSetup vision(arm_model(), c, {});
  const ReportedCovarianceSetup v(vision, sampling_blocks(*vision.model, c));
  EXPECT_EQ(v.states.size(), 8u);
  for (const auto& st : v.states) EXPECT_EQ(st.kind, Kind::kAngle);
  EXPECT_EQ(v.num_consider, 0);
}

// Without model error, an image's update is PosteriorCovariance's: started
// from the prior's variances, the image's information folded in at the
// configured scale times the effective pixel fraction; a re-opened state
// starts again from the broad bias prior.
TEST(ReportedCovariance, AnImageFoldsItsInformationIntoThePriorsVariances) {
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  c.model_error = false;
  c.image_information_scale = 0.3;
  const TrackerSetup setup(arm_model(), c, {"shoulder", "elbow"});
  ReportedCovariance reported(setup, sampling_blocks(*setup.model, c));
  const RobotModel& model = *setup.model;
  DepthModelParams pixels = c.depth_model;
  DepthLikelihood likelihood(pixels);
  likelihood.set_observation(render_truth(model, 0.4, -0.6));
  DepthRenderer renderer(model, kCamera);
  std::vector<double> mean(8, 0.0), prior_std(8, 0.01);
  mean[std::size_t(model.joint_index("shoulder"))] = 0.4;
  mean[std::size_t(model.joint_index("elbow"))] = -0.6;
  prior_std[0] = 0.05;
  std::vector<char> reopened(8, 0);
  EXPECT_TRUE(reported.begin_image(1.0, prior_std, reopened, mean, renderer, likelihood));
  ASSERT_GT(reported.information().pixels_used(), 0);
  TrackingHealth health;
  reported.end_image(1.0, health);

  PosteriorCovariance expected(reported.setup().states);
  Eigen::VectorXd start(expected.size());
  for (int i = 0; i < expected.size(); ++i)
    start[i] = std::pow(prior_std[std::size_t(expected.states()[std::size_t(i)].dof)], 2);
  expected.reset(start, 1.0);
  expected.update(reported.information_matrix(),
                  0.3 * reported.information().effective_pixel_fraction());
  EXPECT_EQ(reported.covariance().covariance(), expected.covariance());
  // The image informs the camera's depth offset (state 4), not the joints'
  // turns about the viewing axis (only edges move).
  EXPECT_LT(reported.covariance().covariance()(4, 4), 0.5 * 0.01 * 0.01);

  // A re-opened state restarts; the refinement is then skipped.
  reopened[0] = 1;
  EXPECT_FALSE(reported.begin_image(2.0, prior_std, reopened, mean, renderer, likelihood));
  EXPECT_EQ(reopened[0], 0);
  EXPECT_EQ(reported.covariance().covariance()(0, 0), reported.setup().reopened_bias_var_rad2);
  EXPECT_EQ(reported.covariance().covariance()(0, 1), 0.0);
}

// The means' lag (mean_lag.h) follows each bias and camera angle as a
// MeanLag fed the same means does; a state a search re-opened starts again.
TEST(ReportedCovariance, TheMeansLagFollowsTheBiasesAndTheCameraAndRestartsWithASearch) {
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  c.model_error = false;
  const TrackerSetup setup(arm_model(), c, {"shoulder", "elbow"});
  ReportedCovariance reported(setup, sampling_blocks(*setup.model, c));
  const RobotModel& model = *setup.model;
  const int shoulder = model.joint_index("shoulder"), camera_x = setup.n_phys;
  ASSERT_EQ(reported.setup().states[0].dof, shoulder);
  ASSERT_EQ(reported.setup().states[2].dof, camera_x);
  JointBelief belief = initial_joint_belief(*setup.filter_model, std::vector<double>{0.0, 0.0});
  MeanLag bias_alone({1}, c.mean_lag_scale, c.mean_lag_time_constant_s);
  MeanLag camera_alone({1}, c.mean_lag_scale, c.mean_lag_time_constant_s);
  for (int k = 0; k <= 300; ++k) {  // 10 s at 30 Hz
    const double t = k / 30.0;
    belief.mean_b[std::size_t(shoulder)] = 0.01 * t;
    belief.mean_a[std::size_t(shoulder)] = t;  // the angle moves with the arm: not followed
    belief.mean_a[std::size_t(camera_x)] = 0.002 * t;
    reported.record_means(t, belief);
    bias_alone.update(t, std::vector{0.01 * t});
    camera_alone.update(t, std::vector{0.002 * t});
  }
  const std::span<const double> lag = reported.mean_lag_variance();
  ASSERT_EQ(lag.size(), reported.setup().states.size());
  EXPECT_GT(lag[0], 0.0);
  EXPECT_EQ(lag[0], bias_alone.variance()[0]);
  EXPECT_EQ(lag[1], 0.0);  // the elbow's bias stands still
  EXPECT_EQ(lag[2], camera_alone.variance()[0]);

  DepthLikelihood likelihood(c.depth_model);
  likelihood.set_observation(render_truth(model, 0.0, 0.0));
  DepthRenderer renderer(model, kCamera);
  std::vector<double> mean(std::size_t(setup.n), 0.0), prior_std(std::size_t(setup.n), 0.01);
  std::vector<char> reopened(std::size_t(setup.n), 0);
  reopened[std::size_t(shoulder)] = 1;
  reported.begin_image(10.0, prior_std, reopened, mean, renderer, likelihood);
  EXPECT_EQ(reported.mean_lag_variance()[0], 0.0);
  EXPECT_EQ(reported.mean_lag_variance()[2], camera_alone.variance()[0]);
}

// The arm with the forearm `forearm_nearer_m` nearer the camera.
std::shared_ptr<const RobotModel> arm_with_forearm_nearer(double forearm_nearer_m) {
  std::string urdf = kArm;
  const std::string elbow = "<origin xyz=\"0 0 0.3\"/>";
  const std::size_t at = urdf.find(elbow);
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos)
    urdf.replace(at, elbow.size(),
                 "<origin xyz=\"" + std::to_string(forearm_nearer_m) + " 0 0.3\"/>");
  return std::make_shared<const RobotModel>(RobotModel::from_urdf_string(urdf, "."));
}

// With model error, each link shift is a consider parameter: one the image
// pins at the estimated model error's standard deviation, one it does not
// pin (the DOFs absorb it) at model_error_unpinned_scale times it, for the
// joints and the camera offset alike. The real arm's forearm sits 8 mm
// nearer the camera than the model's; the base's shift along the view is
// the camera's depth offset, which the DOFs absorb.
TEST(ReportedCovariance, ShiftsTheImageDoesNotPinWidenEveryState) {
  const auto real = arm_with_forearm_nearer(0.008);
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  const TrackerSetup setup(arm_model(), c, {"shoulder", "elbow"});
  const RobotModel& model = *setup.model;
  DepthLikelihood likelihood(c.depth_model);
  likelihood.set_observation(render_truth(*real, 0.4, -0.6));
  DepthRenderer renderer(model, kCamera);
  const std::size_t n = std::size_t(model.num_joints());
  std::vector<double> mean(n, 0.0), prior_std(n, 0.01);
  mean[std::size_t(model.joint_index("shoulder"))] = 0.4;
  mean[std::size_t(model.joint_index("elbow"))] = -0.6;
  prior_std[std::size_t(model.joint_index("shoulder"))] = 0.05;
  prior_std[std::size_t(model.joint_index("elbow"))] = 0.05;

  // One image at unpinned scale `scale`; returns the covariance, and the
  // pinned flags and model error it was made with.
  auto one_image = [&](double scale, std::vector<char>& pinned, double& model_error_m,
                       Eigen::MatrixXd& cross) {
    TrackerConfig cs = c;
    cs.model_error_unpinned_scale = scale;
    const TrackerSetup scaled(setup.model, cs, {"shoulder", "elbow"});
    ReportedCovariance reported(scaled, sampling_blocks(model, cs));
    std::vector<char> reopened(n, 0);
    EXPECT_TRUE(reported.begin_image(1.0, prior_std, reopened, mean, renderer, likelihood));
    TrackingHealth health;
    reported.end_image(1.0, health);
    reported.information().link_shift_variance_m2(&pinned);
    model_error_m = health.model_error_std_m;
    cross = reported.information().motion_field_shift_cross_information();
    // The same update made here from its parts.
    PosteriorCovariance expected(reported.setup().states, reported.setup().num_consider);
    Eigen::VectorXd start(expected.size());
    for (int i = 0; i < expected.size(); ++i)
      start[i] = std::pow(prior_std[std::size_t(expected.states()[std::size_t(i)].dof)], 2);
    expected.reset(start, 1.0);
    // The shifts' columns at the model error, the unpinned ones times the
    // scale, then the bulges' (each at its own size; LinkBulge tests) as
    // the update took them. One image teaches no learned shift: no state
    // takes wider columns.
    Eigen::MatrixXd consider_cross = reported.consider_cross();
    for (int k = 0; k < cross.cols(); ++k)
      consider_cross.col(k) =
          cross.col(k) * (pinned[std::size_t(k)] ? model_error_m : scale * model_error_m);
    EXPECT_EQ(consider_cross, reported.consider_cross());
    // The pixel noise's term as the fitted residuals size it
    // (uncertainty.pixel_noise_after_fit, the default).
    const double fraction = reported.information().effective_pixel_fraction();
    expected.update(reported.information_matrix(), consider_cross, fraction,
                    std::min(1.0, fraction * reported.information().fitted_residual_factor()));
    EXPECT_EQ(reported.covariance().covariance(), expected.covariance()) << "scale " << scale;
    return reported.covariance().covariance();
  };
  std::vector<char> pinned_1, pinned_3;
  double error_1 = 0, error_3 = 0;
  Eigen::MatrixXd cross;
  const Eigen::MatrixXd at_1 = one_image(1.0, pinned_1, error_1, cross);
  const Eigen::MatrixXd at_3 = one_image(3.0, pinned_3, error_3, cross);
  ASSERT_GT(error_1, 0.0);
  EXPECT_EQ(error_1, error_3);
  EXPECT_EQ(pinned_1, pinned_3);
  // Some shift moves the image (a cross term) and is not pinned: scaling it
  // widens the covariance, and never narrows it.
  bool unpinned_seen = false;
  for (int k = 0; k < cross.cols(); ++k)
    unpinned_seen = unpinned_seen || (!pinned_1[std::size_t(k)] && cross.col(k).norm() > 0);
  ASSERT_TRUE(unpinned_seen);
  EXPECT_GT((at_3 - at_1).trace(), 0.0);
  EXPECT_GE(at_3.eigenvalues().real().minCoeff(), -1e-12 * at_3.trace());
  // Some camera offset's variance and some joint's are larger.
  ReportedCovariance states(setup, sampling_blocks(model, c));
  bool camera_wider = false, joint_wider = false;
  for (int i = 0; i < at_1.rows(); ++i) {
    bool& wider =
        states.setup().states[std::size_t(i)].dof >= setup.n_phys ? camera_wider : joint_wider;
    wider = wider || at_3(i, i) > at_1(i, i) * (1 + 1e-9);
  }
  EXPECT_TRUE(camera_wider);
  EXPECT_TRUE(joint_wider);
}

// The health after `images` images of the arm `real` at shoulder 0.4,
// elbow -0.6, `dt_s` apart from 1 s, tracked with `nominal` under `config`.
std::vector<TrackingHealth::LinkModelError> links_after_images(
    std::shared_ptr<const RobotModel> nominal, const RobotModel& real, const TrackerConfig& config,
    int images, double dt_s) {
  const TrackerSetup setup(std::move(nominal), config, {"shoulder", "elbow"});
  const RobotModel& model = *setup.model;
  DepthLikelihood likelihood(config.depth_model);
  likelihood.set_observation(render_truth(real, 0.4, -0.6));
  DepthRenderer renderer(model, kCamera);
  const std::size_t n = std::size_t(model.num_joints());
  std::vector<double> mean(n, 0.0), prior_std(n, 0.01);
  mean[std::size_t(model.joint_index("shoulder"))] = 0.4;
  mean[std::size_t(model.joint_index("elbow"))] = -0.6;
  ReportedCovariance reported(setup, sampling_blocks(model, config));
  std::vector<char> reopened(n, 0);
  TrackingHealth health;
  for (int k = 0; k < images; ++k) {
    const double t = 1.0 + dt_s * k;
    EXPECT_TRUE(reported.begin_image(t, prior_std, reopened, mean, renderer, likelihood));
    reported.end_image(t, health);
  }
  return health.links;
}

// The health names the link that does not fit: the real forearm sits 8 mm
// nearer the camera than the model's (a shift along the view, which the
// joints cannot take up), so after some images the forearm's pinned shift
// reads about 8 mm and the upper arm's about nothing; on the exact arm both
// read about nothing. The base's shift moves the whole arm, which the camera
// offset takes up: no image pins it. Without model_error there is no list.
TEST(ReportedCovariance, TheHealthReportsEachLinksPinnedShift) {
  // 20 s of images 0.5 s apart: the average (2 s) forgets its start at 0.
  auto after_images = [&](double forearm_nearer_m, bool model_error) {
    TrackerConfig c = small_config(TrackingMethod::kFullFusion);
    c.model_error = model_error;
    return links_after_images(arm_model(), *arm_with_forearm_nearer(forearm_nearer_m), c, 40, 0.5);
  };
  const auto off = after_images(0.008, true);
  const auto exact = after_images(0.0, true);
  const std::vector<std::string> names = {"base_link", "upper", "lower"};
  ASSERT_EQ(off.size(), names.size());
  ASSERT_EQ(exact.size(), names.size());
  for (std::size_t g = 0; g < names.size(); ++g) {
    EXPECT_EQ(off[g].link, names[g]);
    EXPECT_EQ(exact[g].link, names[g]);
  }
  EXPECT_TRUE(std::isnan(off[0].shift_m));
  EXPECT_EQ(off[0].images, 0);
  EXPECT_TRUE(std::isnan(exact[0].shift_m));
  EXPECT_EQ(off[2].images, 40);
  EXPECT_NEAR(off[2].shift_m, 0.008, 0.002);
  EXPECT_LT(off[1].shift_m, 0.002);
  EXPECT_LT(exact[1].shift_m, 0.001);
  EXPECT_LT(exact[2].shift_m, 0.001);
  EXPECT_TRUE(after_images(0.008, false).empty());
}

// The arm with a round forearm 8 cm in radius, `scale` times the model's
// size about the elbow (a box's scale cannot be told from a shift where
// three faces show; a thinner one spans too few of the 64x48 pixels).
std::shared_ptr<const RobotModel> arm_with_round_forearm(double scale) {
  std::string urdf = kArm;
  const std::string box =
      R"(<visual><origin xyz="0 0 0.125"/><geometry><box size="0.04 0.08 0.25"/></geometry></visual>)";
  const std::size_t at = urdf.find(box);
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos)
    urdf.replace(at, box.size(),
                 "<visual><origin xyz=\"0 0 " + std::to_string(0.125 * scale) +
                     "\"/><geometry><cylinder radius=\"" + std::to_string(0.08 * scale) +
                     "\" length=\"" + std::to_string(0.25 * scale) + "\"/></geometry></visual>");
  return std::make_shared<const RobotModel>(RobotModel::from_urdf_string(urdf, "."));
}

// The health sizes each link: the real round forearm 4% larger than the
// model's reads about +4% once 30 images have sized it (NaN before), and
// the exact forearm about 0.
TEST(ReportedCovariance, TheHealthReportsALinksScale) {
  const TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  auto forearm_after_images = [&](double forearm_scale, int images) {
    const auto links = links_after_images(arm_with_round_forearm(1.0),
                                          *arm_with_round_forearm(forearm_scale), c, images, 0.1);
    EXPECT_EQ(links.size(), 3u);
    return links.size() == 3 ? links[2] : TrackingHealth::LinkModelError{};
  };
  const TrackingHealth::LinkModelError larger = forearm_after_images(1.04, 40);
  EXPECT_EQ(larger.link, "lower");
  EXPECT_EQ(larger.scale_images, 40);
  EXPECT_NEAR(larger.scale, 0.04, 0.01);  // 0.036
  const TrackingHealth::LinkModelError early = forearm_after_images(1.04, 29);
  EXPECT_EQ(early.scale_images, 29);
  EXPECT_TRUE(std::isnan(early.scale));
  EXPECT_NEAR(forearm_after_images(1.0, 40).scale, 0.0, 0.002);
}

// The reported covariance after 40 poses of the arm whose forearm is
// `forearm_nearer_m` nearer the camera than its model, tracked under
// `config` (its states in ReportedCovarianceSetup order).
// (`step_bound`: the refinement's step-bound covariance instead of the reported one.)
Eigen::MatrixXd covariance_after_poses(const TrackerConfig& config, double forearm_nearer_m,
                                       bool step_bound = false) {
  const TrackerSetup setup(arm_model(), config, {"shoulder", "elbow"});
  const RobotModel& model = *setup.model;
  const auto real = arm_with_forearm_nearer(forearm_nearer_m);
  DepthLikelihood likelihood(config.depth_model);
  DepthRenderer renderer(model, kCamera);
  const std::size_t n = std::size_t(model.num_joints());
  std::vector<double> mean(n, 0.0), prior_std(n, 0.01);
  ReportedCovariance reported(setup, sampling_blocks(model, config));
  std::vector<char> reopened(n, 0);
  TrackingHealth health;
  for (int k = 0; k < 40; ++k) {
    const double t = 1.0 + 0.25 * k;
    const double shoulder = 0.4 + 0.3 * std::sin(0.3 * k), elbow = -0.6 + 0.4 * std::cos(0.2 * k);
    mean[std::size_t(model.joint_index("shoulder"))] = shoulder;
    mean[std::size_t(model.joint_index("elbow"))] = elbow;
    likelihood.set_observation(render_truth(*real, shoulder, elbow));
    EXPECT_TRUE(reported.begin_image(t, prior_std, reopened, mean, renderer, likelihood));
    reported.end_image(t, health);
  }
  return (step_bound ? reported.step_bound_covariance() : reported.covariance()).covariance();
}

// uncertainty.model_error_learned_shifts: the forearm, 8 mm nearer the
// camera than its model (along the joints' axis: the same shift in the
// forearm's own axes in every pose), seen over 40 poses, is learned at
// about its size, larger than the pooled estimate the prior has without:
// the camera's reported variances grow. On the exact arm nothing is
// learned above its noise, and the covariance is the same to the bit.
TEST(ReportedCovariance, ALearnedShiftLargerThanTheEstimateWidensItsPrior) {
  const TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  auto variances_after_poses = [&](double forearm_nearer_m, bool learned) {
    TrackerConfig cs = c;
    cs.model_error_learned_shifts = learned;
    // The 64x48 image's residuals, one offset over few pixels, are
    // correlated throughout: the discount would leave the sums almost
    // nothing to learn from in 40 images.
    cs.discount_correlated_residuals = false;
    return Eigen::VectorXd(covariance_after_poses(cs, forearm_nearer_m).diagonal());
  };
  const Eigen::VectorXd off = variances_after_poses(0.008, false);
  const Eigen::VectorXd on = variances_after_poses(0.008, true);
  const auto& states = ReportedCovarianceSetup(TrackerSetup(arm_model(), c, {"shoulder", "elbow"}),
                                               sampling_blocks(*arm_model(), c))
                           .states;
  ASSERT_EQ(off.size(), Eigen::Index(states.size()));
  // The camera's six (its offset is what the forearm's depth informs most
  // here: the encoders' biases are the bias prior's): 1.21x in all (1.5-2x
  // on y and roll before stop 87, when without the learned shift the
  // camera took the unpinned shifts at the estimate, not scaled).
  double camera_off = 0, camera_on = 0;
  for (std::size_t i = 0; i < states.size(); ++i)
    if (states[i].kind == Kind::kAngle) {
      camera_off += off[Eigen::Index(i)];
      camera_on += on[Eigen::Index(i)];
    }
  EXPECT_GT(camera_on, 1.15 * camera_off);
  EXPECT_EQ(variances_after_poses(0.0, true), variances_after_poses(0.0, false));
}

// uncertainty.model_error_unpinned_scale_on_learned: 40 poses learn the
// forearm (8 mm nearer the camera than its model) on all three axes, so
// the joints take its shifts that one image does not pin at the estimate
// plus the learned excess, not at the unpinned scale: the joints' reported
// variance is smaller. The refinement's step stays bounded by the scaled
// covariance, to the bit. On the exact arm at an unpinned scale of 1
// (nothing learned above the noise) the setting changes nothing.
TEST(ReportedCovariance, ALinkLearnedOnEveryAxisCanLeaveTheJointsUnscaled) {
  const TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  const auto& states = ReportedCovarianceSetup(TrackerSetup(arm_model(), c, {"shoulder", "elbow"}),
                                               sampling_blocks(*arm_model(), c))
                           .states;
  auto joints_after_poses = [&](double forearm_nearer_m, double unpinned_scale,
                                bool scale_on_learned, bool step_bound = false) {
    TrackerConfig cs = c;
    cs.model_error_unpinned_scale = unpinned_scale;
    cs.model_error_unpinned_scale_on_learned = scale_on_learned;
    cs.discount_correlated_residuals = false;  // as above: enough to learn from
    // A 64x48 image of planar poses pins the forearm's axes to a few
    // millimetres, not to 1 mm: learned here to within 5.
    cs.model_error_learned_max_std_m = 0.005;
    const Eigen::MatrixXd covariance = covariance_after_poses(cs, forearm_nearer_m, step_bound);
    double joints_var = 0;
    for (std::size_t i = 0; i < states.size(); ++i)
      if (states[i].kind == Kind::kBias) joints_var += covariance(Eigen::Index(i), Eigen::Index(i));
    return std::pair{covariance, joints_var};
  };
  const auto [scaled, scaled_joints_var] = joints_after_poses(0.008, 3.0, true);
  const auto [unscaled, unscaled_joints_var] = joints_after_poses(0.008, 3.0, false);
  EXPECT_LT(unscaled_joints_var, 0.9 * scaled_joints_var);
  EXPECT_GE(unscaled.eigenvalues().real().minCoeff(), -1e-12 * unscaled.trace());
  EXPECT_EQ(joints_after_poses(0.008, 3.0, false, true).first, scaled);
  EXPECT_EQ(joints_after_poses(0.008, 3.0, true, true).first, scaled);
  EXPECT_TRUE(joints_after_poses(0.0, 1.0, true)
                  .first.isApprox(joints_after_poses(0.0, 1.0, false).first, 1e-9));
}

// uncertainty.link_length_std_m: one consider state per joint origin with
// a length and geometry below it that the camera does not hang from; the
// planar arm's shoulder and elbow (the tool has no geometry, the camera
// hangs from the base).
TEST(ReportedCovariance, EachJointOriginWithALengthIsAConsiderState) {
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  c.link_length_std_m = 0.002;
  const TrackerSetup setup(arm_model(), c, {"shoulder", "elbow"});
  const RobotModel& model = *setup.model;
  const ReportedCovarianceSetup s(setup, sampling_blocks(model, c));
  ASSERT_EQ(s.lengths.size(), 2u);
  const std::vector<int>& with_geometry = model.links_with_geometry();
  const char* names[] = {"upper", "lower"};
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& length = s.lengths[i];
    EXPECT_EQ(model.link_name(length.link), names[i]);
    EXPECT_EQ(length.parent, model.link(length.link).parent);
    EXPECT_TRUE(length.direction_in_parent.isApprox(Eigen::Vector3d::UnitZ()));
    ASSERT_EQ(length.top_shift_links.size(), 1u);
    EXPECT_EQ(with_geometry[std::size_t(length.top_shift_links[0])], length.link);
  }
  EXPECT_EQ(s.num_consider, 4 * int(with_geometry.size()) + 2);
  EXPECT_EQ(s.first_bulge, 3 * int(with_geometry.size()) + 2);  // after the lengths
  c.model_error = false;
  const TrackerSetup lengths_only(arm_model(), c, {"shoulder", "elbow"});
  EXPECT_EQ(ReportedCovarianceSetup(lengths_only, sampling_blocks(model, c)).num_consider, 2);
  c.link_length_std_m = 0;
  const TrackerSetup none(arm_model(), c, {"shoulder", "elbow"});
  const ReportedCovarianceSetup s0(none, sampling_blocks(model, c));
  EXPECT_TRUE(s0.lengths.empty());
  EXPECT_EQ(s0.num_consider, 0);
}

// A joint whose child has no geometry: its length shifts the nearest links
// with geometry below the child, on every branch, and no link below those
// (their own shifts carry their subtrees). Here a bare mount carries the
// upper arm and a side box; the upper arm carries the forearm.
TEST(ReportedCovariance, ALengthAboveABareLinkShiftsTheNearestLinksWithGeometryBelow) {
  std::string urdf = kArm;
  auto replace = [&urdf](const std::string& from, const std::string& to) {
    const std::size_t at = urdf.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    urdf.replace(at, from.size(), to);
  };
  replace(R"(<parent link="base_link"/><child link="upper"/>)",
          R"(<parent link="mount"/><child link="upper"/>)");
  replace("</robot>", R"(<link name="mount"/>
  <link name="side"><visual><geometry><box size="0.03 0.03 0.03"/></geometry></visual></link>
  <joint name="mount_joint" type="fixed"><parent link="base_link"/><child link="mount"/><origin xyz="0 0 0.02"/></joint>
  <joint name="side_joint" type="fixed"><parent link="mount"/><child link="side"/><origin xyz="0 0.1 0"/></joint>
</robot>)");
  TrackerConfig c = small_config(TrackingMethod::kFullFusion);
  c.link_length_std_m = 0.002;
  const TrackerSetup setup(
      std::make_shared<const RobotModel>(RobotModel::from_urdf_string(urdf, ".")), c,
      {"shoulder", "elbow"});
  const RobotModel& model = *setup.model;
  const ReportedCovarianceSetup s(setup, sampling_blocks(model, c));
  const std::vector<int>& with_geometry = model.links_with_geometry();
  auto shifted = [&](const std::string& child) {
    std::vector<std::string> names;
    for (const auto& length : s.lengths)
      if (model.link_name(length.link) == child)
        for (int g : length.top_shift_links)
          names.push_back(model.link_name(with_geometry[std::size_t(g)]));
    std::sort(names.begin(), names.end());
    return names;
  };
  using Names = std::vector<std::string>;
  ASSERT_EQ(s.lengths.size(), 4u);  // not the tool (nothing below) nor the camera
  EXPECT_EQ(shifted("mount"), (Names{"side", "upper"}));
  EXPECT_EQ(shifted("upper"), Names{"upper"});
  EXPECT_EQ(shifted("side"), Names{"side"});
  EXPECT_EQ(shifted("lower"), Names{"lower"});
}

// A stated tolerance's tests: images of the planar arm at (0.4, -0.6) as
// `real` shows it, tracked with `model`, model error off and each image
// counted whole (the effect is clear), the camera's default priors (the
// camera offset is estimated).
struct OnePoseImages {
  OnePoseImages(std::shared_ptr<const RobotModel> tracked, const RobotModel& real)
      : model(std::move(tracked)), likelihood(config.depth_model), renderer(*model, kCamera) {
    likelihood.set_observation(render_truth(real, 0.4, -0.6));
    mean[std::size_t(model->joint_index("shoulder"))] = 0.4;
    mean[std::size_t(model->joint_index("elbow"))] = -0.6;
  }
  static TrackerConfig base_config() {
    TrackerConfig c = small_config(TrackingMethod::kFullFusion);
    c.model_error = false;
    c.discount_correlated_residuals = false;
    c.camera_translation = TrackerConfig{}.camera_translation;
    c.camera_rotation = TrackerConfig{}.camera_rotation;
    return c;
  }
  // The reported covariance with configuration `c` after an image at each of `times_s`.
  PosteriorCovariance after_images(const TrackerConfig& c, const std::vector<double>& times_s) {
    const TrackerSetup setup(model, c, {"shoulder", "elbow"});
    ReportedCovariance reported(setup, sampling_blocks(*model, c));
    std::vector<char> reopened(n, 0);
    TrackingHealth health;
    for (double t : times_s) {
      EXPECT_TRUE(reported.begin_image(t, prior_std, reopened, mean, renderer, likelihood));
      reported.end_image(t, health);
    }
    return reported.covariance();
  }

  TrackerConfig config = base_config();
  std::shared_ptr<const RobotModel> model;
  DepthLikelihood likelihood;
  DepthRenderer renderer;
  std::size_t n = std::size_t(model->num_joints());
  std::vector<double> mean = std::vector<double>(n, 0.0), prior_std = std::vector<double>(n, 0.01);
};

// A stated length error is a consider parameter: it adds to the reported
// covariance what its standard deviation squared times the gain's response
// to it says (consider analysis is linear in the parameters' covariance:
// twice the stated error, four times the addition), and only adds. The
// forearm leans 0.1 m towards the camera, so its length moves its depth,
// which the camera offset (not known here) absorbs in part; the real one
// leans 8 mm further.
TEST(ReportedCovariance, AStatedLengthErrorAddsItsSquareToTheCovariance) {
  OnePoseImages images(arm_with_forearm_nearer(0.1), *arm_with_forearm_nearer(0.108));
  images.prior_std[std::size_t(images.model->joint_index("shoulder"))] = 0.05;
  images.prior_std[std::size_t(images.model->joint_index("elbow"))] = 0.05;
  auto after_two_images = [&](double length_std_m) {
    TrackerConfig c = images.config;
    c.link_length_std_m = length_std_m;
    return images.after_images(c, {1.0, 1.1}).covariance();
  };
  const Eigen::MatrixXd none = after_two_images(0), at_2mm = after_two_images(0.002),
                        at_4mm = after_two_images(0.004);
  const Eigen::MatrixXd added = at_2mm - none;
  EXPECT_GT(added.trace(), 1e-3 * none.trace());
  EXPECT_GE(added.eigenvalues().real().minCoeff(), -1e-9 * added.trace());
  EXPECT_LT((at_4mm - none - 4 * added).norm(), 1e-9 * added.norm());
}

// uncertainty.depth_scale_std: the camera's depth scale is the last
// consider parameter. A scene scaled about the camera's centre is, for a
// surface facing the camera, the camera moved along its optical axis by the
// scale times the depth, which no image can tell apart: over many images
// of one pose the camera's z is left that uncertain (the arm's near faces
// are 0.975-0.98 m from the camera, its base's 0.95), where without it the
// images pin z to a small fraction of that. Linear in the stated variance, as any
// consider parameter (between stated values: without one there is no
// consider analysis, whose pixel-noise term differs, pixel_noise_after_fit).
TEST(ReportedCovariance, AStatedDepthScaleLeavesTheCameraAlongItsAxisThatUncertain) {
  OnePoseImages images(arm_model(), *arm_model());
  const RobotModel& model = *images.model;
  for (int j = 0; j < model.num_joints(); ++j)
    if (model.joint_name(j).starts_with("camera_offset")) images.prior_std[std::size_t(j)] = 0.03;
  std::vector<double> times_s;
  for (int i = 0; i < 40; ++i) times_s.push_back(1 + i / 30.0);
  auto camera_z_std_m = [&](double scale_std) {
    TrackerConfig c = images.config;
    c.depth_scale_std = scale_std;
    const PosteriorCovariance covariance = images.after_images(c, times_s);
    EXPECT_EQ(covariance.num_consider(), scale_std > 0 ? 1 : 0);
    const auto& states = covariance.states();
    const int z = model.joint_index("camera_offset_z");
    for (std::size_t i = 0; i < states.size(); ++i)
      if (states[i].dof == z) return std::sqrt(covariance.covariance()(int(i), int(i)));
    ADD_FAILURE() << "no state for the camera's z";
    return 0.0;
  };
  const double none = camera_z_std_m(0), at_1 = camera_z_std_m(0.01), at_2 = camera_z_std_m(0.02),
               at_3 = camera_z_std_m(0.03);
  EXPECT_NEAR(at_1, 0.01 * 0.97, 0.03 * 0.01 * 0.97);
  EXPECT_LT(none, 0.2 * at_1);
  // (9 - 1) / (4 - 1) times the variance added from 1 to 2 percent.
  EXPECT_NEAR(3 * (at_3 * at_3 - at_1 * at_1), 8 * (at_2 * at_2 - at_1 * at_1), 1e-6 * at_3 * at_3);
}

}  // namespace
}  // namespace arttrack
