// The covariance the tracker reports (docs/method.md, "Reported covariance"):
// PosteriorCovariance (posterior_covariance.h) over the DOFs the particle
// filter samples, each image's information about them (from the motion field,
// image_information.h) folded in after the image's particle filter, and, with
// uncertainty.model_error, the link shifts' variance and each curved link's
// bulge (image_information.h) estimated from the images' residuals as consider
// parameters; with uncertainty.link_length_std_m, each joint origin's length
// error, the user's stated URDF tolerance, as one more consider parameter per
// joint; with uncertainty.model_error_learned_shifts, each link's shift
// learned over many poses (learned_link_shifts.h) widens its prior where it is
// larger; with uncertainty.depth_scale_std, the camera's depth scale, the
// user's stated calibration, as the last consider parameter. Apart from the
// covariance, the means' lag (mean_lag.h) that Tracker::estimate() adds to the
// biases' and the camera offset's reported variances, and, with
// uncertainty.model_error_unpinned_scale_on_learned false, a second covariance
// whose joints keep the unpinned scale, which bounds the mean refinement's
// step (step_bound_covariance()).
//
// An image's update comes in two halves, with the mean's refinement
// (refinement.h) between them: begin_image() moves the covariance to the
// image's time and computes the image's information at the filter's mean;
// end_image() folds it in.
//
// Setup (ReportedCovarianceSetup): the states, the stated lengths and what
// scales the images' information. Workspace: the covariance, the
// information, the model error's running average and the kinematics at
// the image's mean (the lengths' directions). Internal to the tracker
// (tracker/internal: not installed). Not thread-safe: the image thread's.
#pragma once

#include <limits>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/internal/image_information.h"
#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/internal/learned_link_shifts.h"
#include "arttrack/tracker/internal/mean_lag.h"
#include "arttrack/tracker/internal/posterior_covariance.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/tracker.h"

namespace arttrack {

struct ReportedCovarianceSetup {
  // `sampled`: the image filter's sampling blocks.
  ReportedCovarianceSetup(const TrackerSetup& setup, const std::vector<SamplingBlock>& sampled);

  // The states: every DOF the particle filter samples but the encoder
  // joints whose bias is not estimated (their encoder says their angle); a
  // bias for an encoder joint, an angle for the others. `dofs`: theirs.
  std::vector<PosteriorCovariance::State> states;
  std::vector<int> dofs;
  std::vector<char> physical_joint;  // per state: its DOF is a physical joint (not the camera's)
  std::vector<char> camera_offset;   // per state: its DOF is the camera offset's
  // Consider parameters: 3 per link with geometry with model_error (the
  // link shifts, image_information.h), then one per entry of `lengths`,
  // then with model_error one per link with geometry (its bulge,
  // image_information.h: each at the size its own images fit), then with
  // depth_scale_std > 0 the depth's scale (every return (1 + c)
  // times the truth; ImageInformation::depth_scale_cross_information()).
  // Like a length, the images cannot size it: the camera offset moves along
  // its optical axis to take it up (docs/accuracy.md, "A camera's
  // calibration").
  int num_consider = 0;
  int first_bulge = 0, num_bulges = 0;  // the bulges' consider columns
  // uncertainty.link_length_std_m > 0: a joint origin whose length the real
  // robot may not have (the URDF's link lengths are measured, machined and
  // assembled to a tolerance). Its error moves the joint's child link and
  // everything below it along the origin's translation, in the parent
  // link's axes: a shift of `top_shift_links` (indices into the model's
  // links with geometry: the nearest ones at or below the child; each
  // link shift moves its subtree) along `direction_in_parent`. One per
  // joint (fixed ones too) whose origin translates at least 1 mm, that the
  // camera does not hang from (that error is the camera offset's), and
  // with geometry below it. Unlike the shifts, none is estimated from the
  // residuals: the joints and the camera offset absorb a length error along
  // the chain, so the images cannot say how large it is (docs/accuracy.md,
  // stop 57); its size is what the user states.
  struct LengthParameter {
    int link = -1;  // the joint's child link
    int parent = -1;
    Eigen::Vector3d direction_in_parent = Eigen::Vector3d::UnitX();
    std::vector<int> top_shift_links;
  };
  std::vector<LengthParameter> lengths;
  // The rest the constructor sets from the configuration (TrackerConfig,
  // uncertainty.* and acquisition.bias_std_rad), whose defaults live there
  // alone; `information` follows from them.
  double link_length_std_m = 0;
  double depth_scale_std = 0;  // a fraction
  ImageInformationParams information;
  double reopened_bias_var_rad2 = 0;  // (acquisition.bias_std_rad)^2
  double image_information_scale = 0;
  bool discount_correlated_residuals = false;
  bool pixel_noise_after_fit = false;
  bool model_error = false;
  double model_error_time_constant_s = 0;
  double model_error_min_std_m = 0;
  double model_error_unpinned_scale = 0;
  bool model_error_learned_shifts = false;
  double model_error_learned_time_constant_s = 0;
  double model_error_learned_max_std_m = 0;
  bool model_error_unpinned_scale_on_learned = false;
  double mean_lag_scale = 0;  // uncertainty.mean_lag_*
  double mean_lag_time_constant_s = 0;

 private:
  void find_lengths(const RobotModel& model);
};

class ReportedCovariance {
 public:
  ReportedCovariance(const TrackerSetup& setup, const std::vector<SamplingBlock>& sampled);

  const ReportedCovarianceSetup& setup() const { return setup_; }
  const PosteriorCovariance& covariance() const { return covariance_; }
  // The covariance the refinement's step is bounded by (refinement.h): the
  // reported one, but with uncertainty.model_error_unpinned_scale_on_learned
  // false, a second one whose joints keep the unpinned scale on every link,
  // the width stop 55 bounded the step by. The bound is about how far the
  // mean may be off while it converges (a hand re-entering the view), not
  // about the model error the joints carry: at the learned size the step
  // lagged more where a hand leaves and re-enters (docs/accuracy.md, stop
  // 90). Both share the filter's own covariance P (the same updates).
  const PosteriorCovariance& step_bound_covariance() const {
    return step_bound_ ? *step_bound_ : covariance_;
  }

  // The first half of an image's update at time_s: starts the covariance from
  // the prior's angle variances (prior_std per DOF) at the first image, else
  // predicts it to time_s; a DOF re-acquisition moved (`reopened`, cleared
  // here) starts again from the broad prior it was searched with; then the
  // image's information at the robot at `mean` (every DOF), rendered by
  // `renderer` (the likelihood's size; `pool`, when given, shares the
  // renders). Returns whether the mean may be refined on that information:
  // some pixel informed it and no DOF was re-opened. No-op (false) without
  // states.
  bool begin_image(double time_s, std::span<const double> prior_std, std::vector<char>& reopened,
                   std::span<const double> mean, DepthRenderer& renderer,
                   const DepthLikelihood& likelihood, WorkerPool* pool = nullptr);
  // After begin_image(): adds process noise other than time's to the DOFs'
  // states (`added_var` per DOF, >= 0; camera_carrier_motion.h).
  void add_variance(std::span<const double> added_var);
  // After begin_image(): the image's information, and what it knows.
  const ImageInformation& information() const { return information_; }
  // The rigid fits begin_image() computes too (ImageInformation::set_rigid_fit_links).
  void set_rigid_fit_links(const RobotModel& model, std::vector<int> links) {
    information_.set_rigid_fit_links(model, std::move(links));
  }
  // The consider parameters' cross-information the last end_image() took
  // (setup().num_consider columns; a learned shift widens its link's).
  const Eigen::MatrixXd& consider_cross() const { return consider_cross_; }
  // The information end_image() folds in (the motion field's).
  const Eigen::MatrixXd& information_matrix() const {
    return information_.motion_field_information();
  }

  // The second half: folds the image's information in, scaled by
  // image_information_scale (and the effective pixel fraction with
  // discount_correlated_residuals); with model_error, first averages the
  // link shifts' variance over model_error_time_constant_s, which `health`
  // reports (model_error_std_m), and each link's squared shift along the
  // directions the image pins, averaged over the images that pin some, and
  // its scale (health.links). No-op without states.
  void end_image(double time_s, TrackingHealth& health);

  // After end_image(): the means right after the image (the belief's bias
  // for a bias state, its angle for the others) into the means' lag.
  void record_means(double time_s, const JointBelief& belief);
  // Per state, the variance the mean's lag adds to its reported marginal
  // (mean_lag.h); a DOF a search re-opened starts again (begin_image()).
  std::span<const double> mean_lag_variance() const { return mean_lag_.variance(); }

  // The standard deviation of a link's shift the last end_image() took, m
  // (the running estimate, at least model_error_min_std_m; 0 without
  // model_error). The end-effector fit's uncertainty uses it too
  // (end_effector_fit.h).
  double model_error_std_m() const { return model_error_std_m_; }

 private:
  const ReportedCovarianceSetup setup_;
  PosteriorCovariance covariance_;
  // step_bound_covariance()'s own, when it differs (null otherwise), and
  // the consider columns it takes (consider_cross_ before
  // fill_learned_joint_columns()).
  std::unique_ptr<PosteriorCovariance> step_bound_;
  Eigen::MatrixXd step_bound_cross_;
  ImageInformation information_;
  std::shared_ptr<const RobotModel> model_;
  KinematicsState kinematics_;  // at the image's mean, for the lengths' directions
  Eigen::VectorXd start_, q_;
  // uncertainty.model_error: the link shifts' variance averaged over images.
  // (model_error_time_s_: the newest image's; NaN before the first.)
  double model_error_var_m2_ = 0, model_error_time_s_ = std::numeric_limits<double>::quiet_NaN();
  double model_error_std_m_ = 0;
  Eigen::MatrixXd consider_cross_, widened_cross_;
  std::vector<char> pinned_;              // per link shift column: the last image pinned it
  std::vector<double> column_square_m2_;  // per link shift column: its p^2 - noise
  // Per link with geometry: its pinned squared shift averaged over images,
  // and the newest image that pinned it (NaN: none yet).
  std::vector<double> link_square_m2_, link_time_s_;
  // Per link with geometry: the scales' precision-weighted sums (weights
  // and weighted scales) and the newest image that sized it, and the
  // image's fits (workspace).
  std::vector<double> scale_weight_, scale_weighted_, scale_time_s_;
  std::vector<ImageInformation::LinkScaleFit> scale_fits_;
  // Per link with geometry: its bulge's squared fit less noise averaged over
  // the images that fit it, the newest such image (NaN: none yet), and the
  // image's samples (workspace).
  std::vector<double> bulge_square_m2_, bulge_time_s_, bulge_samples_m2_;
  // The bulges' columns of consider_cross_: each link's at its own size.
  void fill_bulge_columns(double time_s);
  MeanLag mean_lag_;           // tracks the biases and the camera offset
  std::vector<double> means_;  // per state, record_means()'s workspace
  void update_link_model_errors(double time_s, TrackingHealth& health);
  // uncertainty.model_error_learned_shifts: the shifts learned over poses
  // (null without) and the image's equations for them (workspace).
  std::unique_ptr<LearnedLinkShifts> learned_;
  ImageInformation::ProjectedShiftEquations shift_equations_;
  // Replaces each link's columns of widened_cross_, the camera offset's
  // (from consider_cross_: prior sd std_m per camera axis the image pinned,
  // unpinned_std_m per other), by the prior with the learned shift's
  // excess over std_m added along every learned link axis: the columns
  // times the Cholesky factor of that covariance (continuous in it, so the
  // consider parameters stay the same ones from image to image). The
  // physical joints keep consider_cross_: a learned shift is one the
  // camera's pose takes up over many poses (the dual arm's pitch, stop
  // 59), and the joints, whose unpinned shifts are already scaled,
  // widened with it went over the band (stop 87).
  void widen_learned_axes(const Eigen::MatrixXd& shift_cross, double std_m, double unpinned_std_m);
  // The learned shift's excess over std_m of link k in camera axes, zero
  // along an axis not learned (covariance over model_error_learned_max_std_m
  // squared); false if it is zero on every axis.
  bool learned_excess_m2(int k, double std_m, Eigen::Matrix3d& excess_m2) const;
  // With uncertainty.model_error_unpinned_scale_on_learned false (the
  // default since stop 91), replaces the columns of consider_cross_ (the
  // joints') of each link learned on all three axes: the prior std_m on
  // every camera axis, plus the learned excess along the axes the image
  // does not pin, instead of unpinned_std_m there. The unpinned scale
  // stands for what is unknown of a shift the joints take up unseen; of a
  // link the poses have learned, the learned size is known (an arm7 length the shoulder takes up in
  // each image is learned larger than std_m: it keeps that size). Adding
  // the excess on the pinned axes too put the dual arm further over the
  // 2 sigma band (docs/accuracy.md, stop 90). After widen_learned_axes(),
  // which keeps the scale for the camera offset.
  void fill_learned_joint_columns(const Eigen::MatrixXd& shift_cross, double std_m);
  // The lengths' columns of consider_cross_ at the image's mean (after
  // begin_image()'s kinematics), from the shifts' cross-information.
  void fill_length_columns(const Eigen::MatrixXd& shift_cross);
};

}  // namespace arttrack
