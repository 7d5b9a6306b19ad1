// The end-effector fit's search along the direction its rigid fit
// determines least (docs/method.md, "End-effector fit").
//
// An image's rigid fit (ImageInformation::rigid_fits()) is one
// Gauss-Newton step over the pixels where the model shows the end link.
// A box-shaped hand slides along its own length without changing the depth
// of its side faces, and the pixels that would show a wrist 6 mm long lie
// past the model's silhouette, where the model shows nothing or what is
// behind: the likelihood explains them as an occluder, and a linear step
// over the model's own pixels cannot see them (docs/accuracy.md, stop 60:
// the right hand 6.8 mm off along its axis, the fit claiming 1 mm). So,
// per fitted end link, the whole pixel likelihood (depth_likelihood.h:
// visible, occluded and outlier terms, pixels past the silhouette among
// them) is evaluated with the link and every link below it drawn at the
// fit's motion moved by s u, u the fit's least-determined translation
// (the largest eigenvector of information^-1's translation block), s on a
// grid of 2 kSteps + 1 points over [-range, range], over the other links
// drawn at the configuration. The grid's best score
// must beat the fit's own pose (s = 0) by kMinGainNats, a likelihood-ratio
// test at about 3 sigma for one parameter (2 x 4.5 = 9 = 3^2), else the
// shift is 0: on a hand that matches its model, noise and pixel steps
// move nothing. Accepted, s is the middle of the run of grid points within
// kPlateauNats of the best (at a pixel's size the score is a staircase).
// The shift is added to the fit's translation (EndEffectorFit::update);
// its scatter over images is part of the reported position covariance.
//
// Setup: the model and the end-effector fit's links. Workspace: the
// kinematics and three images, sized at the first search (no allocation
// after it). Internal to the tracker (tracker/internal: not installed).
// Not thread-safe: the image thread's.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_renderer.h"
#include "arttrack/tracker/internal/depth_likelihood.h"
#include "arttrack/tracker/internal/image_information.h"
#include "arttrack/tracker/kinematics.h"
#include "arttrack/tracker/robot_model.h"

namespace arttrack {

class EndEffectorAxisSearch {
 public:
  static constexpr int kSteps = 5;             // grid points each side of s = 0
  static constexpr double kMinGainNats = 4.5;  // over the fit's own pose
  static constexpr double kPlateauNats = 0.5;  // ties with the best

  // `fit_links`: EndEffectorFit::fit_links(). `range_m`: the largest shift
  // searched (TrackerConfig::end_effector_fit.axis_search_range_m; 0: off).
  // `max_std_m`: a fit whose translation is less determined than this is
  // not searched (EndEffectorFit skips it too).
  EndEffectorAxisSearch(const RobotModel& model, const std::vector<int>& fit_links, double range_m,
                        double max_std_m);

  bool on() const { return range_m_ > 0 && !subtrees_.empty(); }

  // Per fit (fit_links() order, as `fits`): the shift to add to the fit's
  // translation, camera axes, m (0 where none is accepted). `renderer` and
  // `likelihood` are the ones `fits` were computed with (the same camera
  // and image), `q` the configuration they were computed at (every DOF).
  std::span<const Eigen::Vector3d> search(DepthRenderer& renderer,
                                          const DepthLikelihood& likelihood,
                                          std::span<const double> q,
                                          const std::vector<ImageInformation::RigidFit>& fits);

  // Counts since construction: fits searched, shifts accepted.
  int searched() const { return searched_; }
  int accepted() const { return accepted_; }

 private:
  const RobotModel& model_;
  double range_m_ = 0, max_var_m2_ = 0;
  std::vector<LinkSet> subtrees_, others_;  // per fit: its link and those below; the rest
  std::vector<Eigen::Vector3d> shifts_m_;
  KinematicsState at_q_, moved_;
  Eigen::VectorXd q_;
  DepthImage statics_, work_;
  std::vector<double> scores_;
  int searched_ = 0, accepted_ = 0;
};

}  // namespace arttrack
