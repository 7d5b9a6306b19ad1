// The end effectors where the images show them (docs/method.md,
// "End-effector fit"). The real robot is not its URDF: links a few
// millimetres longer or shorter, shapes a few percent bigger. The joint
// angles that best fit every link's pixels then leave the hand where the
// arm's links put it, not where the hand's own pixels do; the nominal
// kinematics at the estimate put the end effector a few millimetres and
// degrees off (realistic/both: the left hand's rotation 2.7 degrees).
//
// After each image (full fusion), the end link's rigid fit
// (ImageInformation::rigid_fits(): a translation and a rotation of the
// nearest link with geometry at or above the end effector, with every
// link below it, fitted to the image's residuals at the particle filter's
// mean; ImageUpdate computes it on the image at
// end_effector_fit.resolution_factor times the likelihood's resolution,
// where the hand's length along its axis spans more than a pixel or two)
// moves the end effector's pose from where that mean's kinematics
// put it; what that is relative to the pose at the image's final mean
// (after the refinement) is the image's correction, in end-effector axes.
// Images whose fit's translation has a standard deviation above
// max_std_m (the hand hidden, edge-on, a few pixels) are skipped. The
// corrections are averaged over time_constant_s (exponentially, each
// image's weight 1 - exp(-dt / time_constant_s)). While no image shows
// the hand the averaged correction fades back to none, by
// exp(-t / time_constant_s), t the time since an image last did: the
// kinematic error it stands for changes with the pose, and the images
// still move the hidden joints (behind a panel a wrist re-balanced by 3
// degrees, and the correction held whole on top of it put the hand 9.7
// mm off at the median where the kinematics alone were 6.0;
// docs/accuracy.md, stop 78). The estimate's end-effector poses are the
// kinematics' at the estimate times the correction (EstimateReport). The
// joint estimate, its covariance and the other methods are unchanged.
//
// The corrected position is as uncertain as the fits it averages, not as
// the angles (whose kinematics it replaces): the fits' scatter about their
// average (exponentially weighted like the corrections, in end-effector
// axes, and not divided by the images' count: neighbouring images' errors
// are the same error), plus the hand's own shape error, a shift of its
// surface by the links' model-error standard deviation in every direction
// (ReportedCovariance::model_error_std_m(), a consider parameter: the rigid
// fit's translation takes a shift up whole), and along the direction the
// fits determine least at uncertainty.model_error_unpinned_scale times it,
// as the joints take a shift no image pins: a box-shaped hand slides along
// its own length without changing the depth of its side faces, and the
// few pixels at its ends that would show a wrist 6 mm long drop out of the
// fit as outliers, which then claims 1 mm where the truth is 6 mm away
// (docs/accuracy.md, stop 60). That direction is the fits' noise
// covariance, information^-1's translation block, scaled to a largest
// eigenvalue of 1 and averaged like the scatter (a smooth shape: the
// whole widening along one direction when one dominates, every direction
// when the fit is isotropic). The size of the fits' own noise model,
// information^-1, is not used, only its shape: over pixels as correlated
// as an exact render's it says 0.9-1.8 mm where the fits scatter by
// 0.15-0.4 mm (docs/accuracy.md, stop 52). With uncertainty.depth_scale_std
// s, the camera's depth scale may be off by s: the fit then puts the hand
// where the scaled image does, s times its distance from the camera along
// its line of sight (scaling about the camera's centre), an error every
// image shares, so s^2 X X^T (X the hand's position in camera axes) is
// added. With end_effector_fit.link_scales, a link of the fitted subtree
// whose shape the images learn to be s larger than its model's (a hand 4%
// bigger; ImageInformation::LinkScaleFit, the health's links[].scale)
// moves every image's fit by s times the fit's response to that scale
// (ImageInformation::RigidFit::scale_cross): an error the images share,
// whose square, averaged like the scatter, is added too. The pooled shape
// error above comes from the links that fit: on a dual arm whose length
// errors sit on links no image pins it reads 0, while its hands, 4% off
// their meshes, sat 2 mm off against a reported 0.9 mm (docs/accuracy.md,
// stop 99). EstimateReport weighs the result against
// the kinematics' by the fits' say (EndEffectorFitEstimate::weight), which
// fades while no image shows the hand.
//
// Setup: the end effectors' fit links, from the TrackerSetup. Workspace:
// the kinematics and the corrections. Internal to the tracker
// (tracker/internal: not installed). Not thread-safe: the image thread's.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "arttrack/tracker/internal/image_information.h"
#include "arttrack/tracker/internal/tracker_setup.h"
#include "arttrack/tracker/kinematics.h"

namespace arttrack {

// A rigid motion in end-effector axes: translation (m), then rotation
// vector (rad). The corrected pose is T_camera_ee * exp(correction).
using EndEffectorCorrection = Eigen::Matrix<double, 6, 1>;

// exp of a correction: the rigid motion it stands for.
Eigen::Isometry3d correction_transform(const EndEffectorCorrection& c);

// The rigid motion an image's fit says, camera axes (X -> R (X - o) + o +
// t, one Gauss-Newton step: information^-1 gradient), and its
// translation's noise covariance (information^-1's, m^2). False when the
// fit is not determined (no pixels, information not positive definite) or
// its translation's variance exceeds max_var_m2 along a camera axis (the
// image barely shows the link).
bool rigid_fit_motion(const ImageInformation::RigidFit& fit, double max_var_m2,
                      Eigen::Isometry3d& motion, Eigen::Matrix3d& translation_noise_m2);

// The shift of `point_m` (camera axes) that the learned shape scales of
// the fit's links (`link_scales`, per link with geometry; NaN or 0: none)
// move the rigid fit by, each link's s information^-1 G^T h (RigidFit),
// summed as outer products, m^2: the links' scales are independent.
Eigen::Matrix3d scale_shift_m2(const ImageInformation::RigidFit& fit,
                               std::span<const double> link_scales, const Eigen::Vector3d& point_m);

// What the fits say about one end effector.
struct EndEffectorFitEstimate {
  // The averaged correction, times exp(-t / time_constant_s) while held
  // (t the time since the last image that showed the end effector).
  EndEffectorCorrection correction = EndEffectorCorrection::Zero();
  // The fits' say in the reported pose, in [0, 1): their total weight in
  // the correction, 1 - prod(1 - w) over the images that showed the end
  // effector (the rest, 1 - weight, is 0: the kinematics' own pose), times
  // exp(-t / time_constant_s), t the time since the last image that did.
  // A held correction stands for a kinematic error that changes with the
  // pose: it and its uncertainty go back to the kinematics' (an image now
  // and then that the fit skips, a few images, costs little).
  double weight = 0;
  // The covariance of the fits' end-effector position, m^2, in the end
  // effector's own axes (at the kinematics' pose): the scatter plus the
  // shape error (above; 0 while weight is 0).
  Eigen::Matrix3d position_covariance_m2 = Eigen::Matrix3d::Zero();
};

class EndEffectorFit {
 public:
  explicit EndEffectorFit(const TrackerSetup& setup);

  // Full fusion with TrackerConfig::end_effector_fit, and some end effector
  // at or below a link with geometry that the camera does not hang from.
  bool on() const { return on_; }
  // The links to fit (ImageInformation::set_rigid_fit_links), one per
  // fitted end effector.
  const std::vector<int>& fit_links() const { return fit_links_; }

  // After an image at time_s: `fits` the image's rigid fits (fit_links()
  // order) at `mean_fitted`, `mean_final` the image's final mean (both
  // every DOF); `model_error_std_m` the links' shape error (above).
  // `axis_shifts_m` (fit_links() order, camera axes; empty: none): added
  // to each fit's translation (end_effector_axis_search.h). `link_scales`
  // (per link with geometry, ImageInformation::shift_links() order; NaN
  // where not learned; empty: none): the links' learned shape scales,
  // taken with end_effector_fit.link_scales.
  void update(double time_s, const std::vector<ImageInformation::RigidFit>& fits,
              std::span<const double> mean_fitted, std::span<const double> mean_final,
              double model_error_std_m, std::span<const Eigen::Vector3d> axis_shifts_m = {},
              std::span<const double> link_scales = {});

  // Per end effector (TrackerConfig::end_effectors order): the averaged
  // correction and its uncertainty (a zero correction of weight 0 until an
  // image shows it, and for an end effector with no link with geometry at
  // or above it).
  const std::vector<EndEffectorFitEstimate>& estimates() const { return estimates_; }

 private:
  const TrackerSetup& setup_;
  bool on_ = false;
  double time_constant_s_ = 1, max_var_m2_ = 0;
  std::vector<int> fit_links_;  // per fitted end effector
  std::vector<int> fitted_ee_;  // per fitted end effector: its index among the end effectors
  std::vector<EndEffectorFitEstimate> estimates_;
  // Per end effector, the fits' translations' weighted scatter about the
  // correction, m^2 (their total weight times their average's), and that
  // total weight (EndEffectorFitEstimate::weight without the decay), and
  // the last image's time that showed it.
  std::vector<Eigen::Matrix3d> scatter_m2_;
  std::vector<double> fits_weight_, last_seen_s_;
  // Per end effector, the fits' averaged correction (what
  // EndEffectorFitEstimate::correction is while an image shows the hand).
  std::vector<EndEffectorCorrection> average_;
  // Per end effector, the fits' noise shape in end-effector axes (above),
  // averaged like the scatter.
  std::vector<Eigen::Matrix3d> weak_shape_;
  // Per end effector, the learned link scales' shift of its position
  // (above), m^2 in end-effector axes, averaged like the scatter.
  std::vector<Eigen::Matrix3d> link_scale_m2_;
  bool link_scales_ = false;
  double unpinned_scale_ = 1;
  double depth_scale_std_ = 0;
  // Per fitted end effector, the last image's: whether it determined the
  // fit, the motion (then the end effector's pose) it says, and its
  // translation's noise covariance in camera axes, m^2.
  std::vector<char> seen_;
  std::vector<Eigen::Isometry3d> motions_;
  std::vector<Eigen::Matrix3d> noise_m2_;
  std::vector<Eigen::Matrix3d> scale_shift_m2_;  // camera axes, at the fitted mean
  std::size_t ee_of(std::size_t f) const { return std::size_t(fitted_ee_[f]); }
  double last_time_s_ = 0;
  bool started_ = false;
  KinematicsState kinematics_;
  Eigen::VectorXd q_;
};

}  // namespace arttrack
