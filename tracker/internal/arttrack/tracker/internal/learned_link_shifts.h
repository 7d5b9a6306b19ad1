// Link shifts learned over many poses (docs/method.md, "Reported
// covariance"; docs/accuracy.md, stop 59). A URDF error is fixed in its
// link's own frame: a joint origin a few millimetres long moves the link
// and everything below it by the same vector in the link's (or, along the
// joint's axis, its parent's) axes in every pose. One image cannot size a
// shift the joints take up, nor one of a link whose surface it hardly
// sees; the same shift seen from other poses can be.
//
// Each image's link-shift normal equations with its DOFs projected out
// (ImageInformation::ProjectedShiftEquations, in camera axes), weighed by
// `weight` / noise_var (the caller's effective pixel fraction: correlated
// pixels count once), are turned into each link's own axes and summed over
// images, each image's sum kept by exp(-dt / time_constant_s). solve()
// gives every link's shift at once, with the covariance the sum's inverse.
// That covariance counts images of one pose as independent when they carry
// one error, so it is several times too small (stop 59: 0.05-0.5 mm where
// the fits sit millimetres from the truth); use it to tell a learned axis
// from an unlearned one, not as the shift's uncertainty. An axis no image
// informs reads 0 with variance kUnlearnedVar_m2.
//
// Setup: the number of links with geometry and the time constant.
// Workspace: the sums and the solve (sized at construction: allocation-free
// after it). Internal to the tracker (tracker/internal: not installed). Not
// thread-safe: the image thread's.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "arttrack/tracker/internal/image_information.h"

namespace arttrack {

class LearnedLinkShifts {
 public:
  // The variance solve() gives an axis no image informed, m^2 (1 m^2).
  static constexpr double kUnlearnedVar_m2 = 1.0;

  LearnedLinkShifts(int num_links, double time_constant_s);

  int num_links() const { return num_links_; }

  // Adds one image at time_s (non-decreasing): `equations` over the link
  // shifts' camera-axis columns (3 k + a: axis a of link k), the camera's
  // pose in each link's frame (`T_link_camera`, num_links()), and the
  // image's weight (> 0). An image that fitted nothing (noise_var 0) only
  // ages the sums.
  void add_image(double time_s, const ImageInformation::ProjectedShiftEquations& equations,
                 std::span<const Eigen::Isometry3d> T_link_camera, double weight);

  // Solves the sums: shift_m() and covariance_m2() per link, in its axes.
  void solve();
  const Eigen::Vector3d& shift_m(int link) const { return shift_m_[std::size_t(link)]; }
  const Eigen::Matrix3d& covariance_m2(int link) const { return covariance_m2_[std::size_t(link)]; }

 private:
  int num_links_ = 0;
  double time_constant_s_ = 10;
  double last_time_s_;                                         // NaN before the first image
  Eigen::MatrixXd information_, system_, inverse_, identity_;  // 3 links square
  Eigen::VectorXd gradient_;
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
  std::vector<Eigen::Vector3d> shift_m_;
  std::vector<Eigen::Matrix3d> covariance_m2_;
};

}  // namespace arttrack
