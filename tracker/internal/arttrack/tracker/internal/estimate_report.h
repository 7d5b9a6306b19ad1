// What Tracker::estimate() reports from the tracker's state (TrackerEstimate,
// tracker.h): angles and biases with their standard deviations, the camera
// offset, the end effectors' poses in the camera frame and their 6x6
// covariances.
//
// The end-effector poses: the kinematics' at the estimate, times the
// end-effector fit's correction (end_effector_fit.h) where there is one;
// TrackerEstimate::ee_image_correction says by how much. Their covariances
// are the joints' through the kinematics (camera_link_jacobian(),
// kinematics.h), the position's weighed against the fits' where the fit
// has a say (end_effector_fit.h).
//
// The standard deviations: for encoders_only, the reading's noise and the
// bias prior's stationary variance (the bias it does not estimate);
// otherwise the joint filters' angle variance, but never below the
// encoder's noise, and, after the first image, the reported covariance's
// marginals (reported_covariance.h) predicted to the estimate's time for
// the DOFs the images inform, each plus what its mean's lag adds
// (mean_lag.h). End-effector covariances are J C J^T, J the
// kinematics' Jacobian in the camera frame (position, and the rotation
// vector of the change), C the DOFs' covariance.
//
// Setup: the tracker's (tracker_setup.h). Workspace: the kinematics it
// evaluates. Internal to the tracker (tracker/internal: not installed). Not
// thread-safe: the tracker calls it under its lock.
#pragma once

#include <span>

#include <Eigen/Core>

#include "arttrack/tracker/internal/end_effector_fit.h"
#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/internal/posterior_covariance.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/tracker.h"

namespace arttrack {

class EstimateReport {
 public:
  explicit EstimateReport(const TrackerSetup& setup);

  // The estimate at time_s of `belief` (DOF order), with the newest encoder
  // readings (physical DOFs; what encoders_only reports) and the reported
  // covariance (not started: none yet). Leaves e.health alone. `e` may
  // hold an earlier estimate: every field is overwritten, in its storage.
  // `mean_lag_var`: per state of `covariance`, the variance its mean's lag
  // adds (empty: none). `fits`: per end effector, the end-effector fit's
  // (none: empty).
  void fill(const JointBelief& belief, std::span<const double> readings_rad, double time_s,
            const PosteriorCovariance& covariance, std::span<const double> mean_lag_var,
            std::span<const EndEffectorFitEstimate> fits, TrackerEstimate& e);

 private:
  const TrackerSetup& setup_;
  KinematicsState kinematics_;
  Eigen::VectorXd q_;
  Eigen::MatrixXd angle_cov_, dof_cov_;  // the states' reported angle covariance; the DOFs'
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_, jacobian_cov_;  // J, J C
};

}  // namespace arttrack
