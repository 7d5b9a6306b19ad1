#include "arttrack/tracker/internal/learned_link_shifts.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <cmath>
#include <vector>

namespace arttrack {
namespace {

using Equations = ImageInformation::ProjectedShiftEquations;

// One image's equations for shifts `shift_link_m` (link axes) of links
// whose camera poses are `T_link_camera`, when the image sees only depth
// (camera z) of each link, `information` per link: b = A s in camera axes.
Equations depth_only_image(const std::vector<Eigen::Isometry3d>& T_link_camera,
                           const std::vector<Eigen::Vector3d>& shift_link_m, double information,
                           double noise_var) {
  Equations e;
  const int links = int(T_link_camera.size());
  for (int k = 0; k < links; ++k)
    for (int a = 0; a < 3; ++a) e.columns.push_back(3 * k + a);
  e.A = Eigen::MatrixXd::Zero(3 * links, 3 * links);
  e.b = Eigen::VectorXd::Zero(3 * links);
  for (int k = 0; k < links; ++k) {
    const Eigen::Vector3d shift_camera_m =
        T_link_camera[std::size_t(k)].linear().transpose() * shift_link_m[std::size_t(k)];
    e.A(3 * k + 2, 3 * k + 2) = information;
    e.b[3 * k + 2] = information * shift_camera_m.z();
  }
  e.noise_var = noise_var;
  return e;
}

Eigen::Isometry3d turned(double angle_rad, const Eigen::Vector3d& axis) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  return T;
}

// A link's pose in image i: turned about an axis that itself turns, so
// that the camera's depth axis sweeps every direction in the link's axes.
Eigen::Isometry3d pose(int i, double phase) {
  return turned(0.4 + 0.07 * i, {std::cos(0.5 * i + phase), std::sin(0.5 * i + phase), 0.7});
}

// One image sees a link's shift along its depth only; as the link turns
// from image to image, the same shift in the link's own axes is pinned in
// all three, to the information the images sum to in the link's axes
// (sum of w a r r^T, r the camera's depth axis in the link's axes: the
// brute-force sum here). A link no image shows reads 0 with the unlearned
// variance.
TEST(LearnedLinkShifts, AShiftFixedInItsLinkIsLearnedFromPosesThatEachSeeOneAxis) {
  const std::vector<Eigen::Vector3d> truth_m = {{0.004, -0.002, 0.006}, {0, 0, 0}};
  const double information = 4e6, weight = 0.5, noise_var = 2.0;
  LearnedLinkShifts shifts(3, 1e9);  // no forgetting over the test's 1.3 s
  Eigen::Matrix3d summed = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 40; ++i) {
    const std::vector<Eigen::Isometry3d> T = {pose(i, 0), pose(i, 1), pose(0, 2)};
    const Equations e = depth_only_image({T[0], T[1]}, truth_m, information, noise_var);
    shifts.add_image(i / 30.0, e, T, weight);  // link 2: not shown
    const Eigen::Vector3d r = T[0].linear().col(2);
    summed += weight / noise_var * information * r * r.transpose();
    if (i == 0) {
      shifts.solve();
      // One pose: the depth is learned, the two axes across it are not.
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(shifts.covariance_m2(0));
      EXPECT_GT(eig.eigenvalues()[1], 1.0);
      EXPECT_LT(eig.eigenvalues()[0], 1e-5);
    }
  }
  shifts.solve();
  EXPECT_LT((shifts.shift_m(0) - truth_m[0]).norm(), 1e-9);
  EXPECT_LT(shifts.shift_m(1).norm(), 1e-9);
  EXPECT_TRUE(shifts.covariance_m2(0).isApprox(summed.inverse(), 1e-6));
  // 1e6 per image over 40 images and three axes: about 0.3 mm on each.
  for (int a = 0; a < 3; ++a) EXPECT_LT(std::sqrt(shifts.covariance_m2(0)(a, a)), 5e-4);
  EXPECT_EQ(shifts.shift_m(2), Eigen::Vector3d::Zero());
  EXPECT_EQ(shifts.covariance_m2(2),
            Eigen::Matrix3d::Identity() * LearnedLinkShifts::kUnlearnedVar_m2);
}

// The sums forget with the time constant: after 100 s of images of a new
// shift, the old one has faded; an image that fitted nothing adds nothing.
TEST(LearnedLinkShifts, OldImagesFadeWithTheTimeConstant) {
  const std::vector<Eigen::Isometry3d> T = {pose(0, 0)};
  LearnedLinkShifts shifts(1, 2.0);
  for (int i = 0; i < 30; ++i) {
    const std::vector<Eigen::Isometry3d> Ti = {pose(i, 0)};
    shifts.add_image(0.1 * i, depth_only_image(Ti, {{0.01, 0, 0}}, 1e6, 1.0), Ti, 1.0);
  }
  for (int i = 0; i < 30; ++i) {
    const std::vector<Eigen::Isometry3d> Ti = {pose(i, 0)};
    shifts.add_image(100 + 0.1 * i, depth_only_image(Ti, {{0, 0.003, 0}}, 1e6, 1.0), Ti, 1.0);
  }
  Equations nothing;  // noise_var 0: the image fitted no shift
  shifts.add_image(103.0, nothing, T, 1.0);
  shifts.solve();
  EXPECT_LT((shifts.shift_m(0) - Eigen::Vector3d(0, 0.003, 0)).norm(), 1e-6);
}

}  // namespace
}  // namespace arttrack
