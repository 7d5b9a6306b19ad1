#include "arttrack/tracker/internal/learned_link_shifts.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace arttrack {

LearnedLinkShifts::LearnedLinkShifts(int num_links, double time_constant_s)
    : num_links_(num_links),
      time_constant_s_(time_constant_s),
      last_time_s_(std::numeric_limits<double>::quiet_NaN()),
      information_(Eigen::MatrixXd::Zero(3 * num_links, 3 * num_links)),
      system_(3 * num_links, 3 * num_links),
      inverse_(3 * num_links, 3 * num_links),
      identity_(Eigen::MatrixXd::Identity(3 * num_links, 3 * num_links)),
      gradient_(Eigen::VectorXd::Zero(3 * num_links)),
      ldlt_(3 * num_links),
      shift_m_(std::size_t(num_links), Eigen::Vector3d::Zero()),
      covariance_m2_(std::size_t(num_links), Eigen::Matrix3d::Identity() * kUnlearnedVar_m2) {}

void LearnedLinkShifts::add_image(double time_s,
                                  const ImageInformation::ProjectedShiftEquations& equations,
                                  std::span<const Eigen::Isometry3d> T_link_camera, double weight) {
  if (!std::isnan(last_time_s_)) {
    const double keep = std::exp(-std::max(0.0, time_s - last_time_s_) / time_constant_s_);
    information_ *= keep;
    gradient_ *= keep;
  }
  last_time_s_ = time_s;
  if (!(equations.noise_var > 0) || std::ssize(T_link_camera) != num_links_) return;
  const double w = weight / equations.noise_var;
  const std::vector<int>& columns = equations.columns;
  // Camera axis a of link k is, in k's axes, column a of R_link_camera:
  // A_link = R A_camera R^T over each pair of links' blocks.
  for (std::size_t i = 0; i < columns.size(); ++i) {
    const int li = columns[i] / 3;
    const Eigen::Vector3d ri = T_link_camera[std::size_t(li)].linear().col(columns[i] % 3);
    gradient_.segment<3>(3 * li) += w * equations.b[Eigen::Index(i)] * ri;
    for (std::size_t j = 0; j < columns.size(); ++j) {
      const int lj = columns[j] / 3;
      const Eigen::Vector3d rj = T_link_camera[std::size_t(lj)].linear().col(columns[j] % 3);
      information_.block<3, 3>(3 * li, 3 * lj).noalias() +=
          (w * equations.A(Eigen::Index(i), Eigen::Index(j))) * ri * rj.transpose();
    }
  }
}

void LearnedLinkShifts::solve() {
  const int n = 3 * num_links_;
  if (n == 0) return;
  system_ = information_;
  // An axis no image informed: a unit diagonal, so it reads 0 with variance
  // 1 m^2; a small ridge keeps the rest solvable.
  const double ridge = 1e-9 * std::max(1.0, information_.diagonal().maxCoeff());
  for (int i = 0; i < n; ++i)
    system_(i, i) = system_(i, i) > 0 ? system_(i, i) + ridge : 1.0 / kUnlearnedVar_m2;
  ldlt_.compute(system_);
  inverse_ = ldlt_.solve(identity_);
  for (int k = 0; k < num_links_; ++k) {
    shift_m_[std::size_t(k)] = inverse_.middleRows<3>(3 * k) * gradient_;
    covariance_m2_[std::size_t(k)] = inverse_.block<3, 3>(3 * k, 3 * k);
  }
}

}  // namespace arttrack
