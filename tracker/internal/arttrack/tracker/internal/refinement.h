// The mean's refinement after an image's particle filter (docs/method.md,
// "Refinement"; full fusion with refinement.enabled): one Gauss-Newton step
// on the filter's target, prior x likelihood^beta, from the image's
// information and gradient at the filter's mean (MeanRefinement,
// mean_refinement.h, solves it; the trust region widens to the reported
// standard deviations while the step is longer than
// refinement.widen_beyond_sigma of them), then the full step or its half when it
// raises that target with the exact pixel model (occlusion, outliers and
// edges included); otherwise the mean stays.
//
// Setup: whether it runs and the solver's parameters. Workspace: the solver
// and the step's scratch. States are the reported covariance's
// (reported_covariance.h), in its order. Internal to the tracker
// (tracker/internal: not installed). Not thread-safe: the image thread's.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "arttrack/tracker/internal/image_filter.h"
#include "arttrack/tracker/internal/image_information.h"
#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/internal/posterior_covariance.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "mean_refinement.h"

namespace arttrack {

class Refinement {
 public:
  // `states`: the reported covariance's.
  Refinement(const TrackerSetup& setup, const std::vector<PosteriorCovariance::State>& states);

  // Full fusion with refine_mean.
  bool on() const { return on_; }

  // Refines `belief`'s angle means on the image's information (computed at
  // them) under the prior N(prior_mean, P) of the image, P the covariance's
  // nominal angle covariance, no state moving further than its prior_std
  // (per DOF), or its reported standard deviation where larger when the
  // step is longer than widen_beyond_sigma of them (the reported
  // covariance's). Folds the step taken into `belief` (fold_angle_marginal,
  // the variances kept). Returns whether a step was taken.
  bool refine(const PosteriorCovariance& covariance, const ImageInformation& information,
              std::span<const double> prior_mean, std::span<const double> prior_std,
              ImageFilter& image, JointBelief& belief);
  // After refine(): how many directions of the states its step found that
  // move no surface (MeanRefinement::unseen_directions()).
  int unseen_directions() const { return solver_.unseen_directions(); }

 private:
  // Setup.
  bool on_ = false;
  double widen_beyond_sigma_ = 0;
  // Workspace.
  MeanRefinement solver_;
  Eigen::VectorXd x_;  // theta - mu per state
  std::vector<double> spread_;
  std::vector<double> q_;
  Eigen::MatrixXd nominal_;   // the filter's angle covariance (its weights)
  Eigen::MatrixXd reported_;  // the reported angle covariance
};

}  // namespace arttrack
