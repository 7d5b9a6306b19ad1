// One depth image's update of the joint belief (docs/method.md, "Image
// update" and "Beyond the paper"), between the prior the tracker predicted
// to the image's time and the re-filtering of the readings after it (paper
// Sec. IV-C, the tracker's): the camera offset's walk with the joints that
// carry the camera (camera_carrier_motion.h); the particle filter over the image
// (image_filter.h), or at the first image the acquisition's search
// (acquisition.h); the re-acquisition the health check's counts call for;
// the joints the image cannot see given their prior back (unseen_joints.h;
// not after a search);
// the reported covariance (reported_covariance.h) with the mean's
// refinement (refinement.h) between its halves; the end-effector fit
// (end_effector_fit.h), on the image at its own, finer resolution with a
// renderer, pixel model and ImageInformation of its own, with its search
// along each hand (end_effector_axis_search.h; on unless
// end_effector_fit.axis_search_range_m is 0); and the health
// check of the result (health_check.h).
//
// Setup: the TrackerSetup and each component's own. Workspace: the
// components' and the image's prior spread. Internal to the tracker
// (tracker/internal: not installed). Not thread-safe: one image at a time,
// on the thread that applies it, without the tracker's lock.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/internal/acquisition.h"
#include "arttrack/tracker/internal/camera_carrier_motion.h"
#include "arttrack/tracker/internal/end_effector_axis_search.h"
#include "arttrack/tracker/internal/end_effector_fit.h"
#include "arttrack/tracker/internal/image_filter.h"
#include "arttrack/tracker/internal/joint_filter.h"
#include "arttrack/tracker/internal/posterior_covariance.h"
#include "arttrack/tracker/internal/refinement.h"
#include "arttrack/tracker/internal/reported_covariance.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "arttrack/tracker/internal/unseen_joints.h"
#include "arttrack/tracker/tracker.h"

namespace arttrack {

class HealthCheck;

class ImageUpdate {
 public:
  explicit ImageUpdate(const TrackerSetup& setup);
  ~ImageUpdate();

  // Whether apply() wants the encoder readings at the image's time (the
  // searches re-open the biases around them).
  bool wants_readings() const { return acquisition_.on(); }

  // Builds what draws the robot for `camera` (full resolution): the
  // simplified meshes and the renderers (RenderGeometry::use_camera), the
  // end-effector fit's too. apply() does it at the first image, or for a
  // camera of other intrinsics.
  void prepare(const CameraIntrinsics& camera);

  // Updates `belief`, the prior at time_s (the image's stamp_s minus the
  // camera delay), with `image` at the likelihood's resolution, taken by
  // `camera` (full resolution). `reading_at_time` (DOF order; empty: none)
  // lets the searches after the first image run. Returns the search's time
  // in ms (0: none ran).
  // `fit_image`: the image at the end-effector fit's resolution (empty:
  // the fit uses `image`).
  double apply(const DepthImage& image, const DepthImage& fit_image, const CameraIntrinsics& camera,
               double stamp_s, double time_s, std::span<const double> reading_at_time,
               JointBelief& belief);

  // The size the end-effector fit sees an image of width x height at:
  // end_effector_fit.resolution_factor times the likelihood's, at most the
  // image's own. False (the fit uses the likelihood's image) when that is no
  // finer than the likelihood's, or the fit is off.
  bool fit_image_size(int width, int height, int& fit_width, int& fit_height) const;

  // After apply(): what the tracker publishes and counts.
  const TrackingHealth& health() const { return health_; }
  const PosteriorCovariance& covariance() const { return covariance_.covariance(); }
  // Per state of covariance(), what the mean's lag adds to its variance
  // (mean_lag.h).
  std::span<const double> mean_lag_variance() const { return covariance_.mean_lag_variance(); }
  // Per end effector, the end-effector fit's correction and its
  // uncertainty (end_effector_fit.h).
  const std::vector<EndEffectorFitEstimate>& end_effector_fits() const {
    return end_effector_fit_.estimates();
  }
  const ImageFilter& filter() const { return filter_; }
  const RenderGeometry& geometry() const { return filter_.geometry(); }
  int geometry_builds() const { return geometry_builds_; }

 private:
  // `camera` subsampled to the likelihood's resolution.
  CameraIntrinsics likelihood_camera(const CameraIntrinsics& camera) const;
  // The plain run's proposal spread: prior_std_, with the camera blocks
  // whose turn it is not (particle_filter.camera_blocks_per_image) held at
  // their mean (spread 0: they cost nothing, and keep their prior).
  std::span<const double> proposal_std_in_turn();

  const TrackerSetup& setup_;
  ImageFilter filter_;
  std::unique_ptr<HealthCheck> health_check_;
  TrackingHealth health_;  // the image thread's; the tracker publishes copies
  Acquisition acquisition_;
  ReportedCovariance covariance_;
  Refinement refinement_;
  UnseenJoints unseen_joints_;
  EndEffectorFit end_effector_fit_;
  EndEffectorAxisSearch axis_search_;
  CameraCarrierMotion carrier_motion_;
  // The end-effector fit's own view, at its finer resolution: the robot
  // drawn for that camera, the pixel model and the rigid fits (no DOFs).
  std::unique_ptr<RenderGeometry> fit_geometry_;
  std::unique_ptr<DepthLikelihood> fit_likelihood_;
  std::unique_ptr<ImageInformation> fit_information_;
  // The fit's view made for `camera` (full resolution) when it sees the
  // image finer than the likelihood; false when it does not.
  bool prepare_fit_view(const CameraIntrinsics& camera);
  // The rigid fits at the image's finer resolution (fit_image), or nullptr
  // when fit_image is empty.
  const std::vector<ImageInformation::RigidFit>* fine_rigid_fits(const DepthImage& fit_image,
                                                                 const CameraIntrinsics& camera);
  // Per image: the prior's angle means and standard deviations (DOF order),
  // and the DOFs re-acquisition moved.
  std::vector<double> prior_mean_, prior_std_;
  // Per image: the variance the camera's carrying joints' motion adds (DOF
  // order; carrier_motion_).
  std::vector<double> carrier_added_var_;
  // The mean the image's information is computed at (before the refinement).
  std::vector<double> mean_fitted_;
  // Per link with geometry: the health's learned scale, for the end-effector fit.
  std::vector<double> link_scales_;
  std::vector<char> reopened_;
  // The camera blocks (indices into the filter's blocks), how many an
  // image samples (the n-th image from the (n m)-th on, cyclically), and
  // the plain run's proposal spread.
  std::vector<int> camera_blocks_;
  int camera_blocks_per_image_ = 0;
  std::vector<double> proposal_std_;
  int images_seen_ = 0;
  int geometry_builds_ = 0;
};

}  // namespace arttrack
