// ReportedCovariance (tracker/internal): the states of the covariance the
// tracker reports, and an image's update of it.
#include "arttrack/tracker/internal/reported_covariance.h"

#include <gtest/gtest.h>

#include <cmath>

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
  EXPECT_EQ(s.num_consider, 3 * int(fusion.model->links_with_geometry().size()));

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

}  // namespace
}  // namespace arttrack
