#include "arttrack/tracker/image_information.h"

#include <algorithm>
#include <cmath>

#include "arttrack/tracker/error.h"

namespace arttrack {

ImageInformation::ImageInformation(std::vector<int> dofs, const ImageInformationParams& params)
    : dofs_(std::move(dofs)), params_(params) {
  if (!(params_.revolute_step_rad > 0) || !(params_.prismatic_step_m > 0) ||
      !(params_.inlier_sigmas > 0))
    throw InputError("image information: steps and inlier_sigmas must be > 0");
}

const Eigen::MatrixXd& ImageInformation::compute(DepthRenderer& renderer, std::span<const double> q,
                                                 const DepthLikelihood& likelihood) {
  const RobotModel& model = renderer.model();
  if (int(q.size()) != model.num_joints())
    throw InputError("image information: configuration has " + std::to_string(q.size()) +
                     " values, the model " + std::to_string(model.num_joints()) + " DOFs");
  if (renderer.camera().width != likelihood.width() ||
      renderer.camera().height != likelihood.height())
    throw InputError("image information: the renderer's camera and the likelihood differ in size");
  const int num_pixels = likelihood.width() * likelihood.height();
  const int m = int(dofs_.size());
  if (kinematics_.T_root_link.empty()) kinematics_ = KinematicsState(model);
  q_ = Eigen::Map<const Eigen::VectorXd>(q.data(), Eigen::Index(q.size()));
  gradients_.setZero(num_pixels, m);
  used_.assign(std::size_t(num_pixels), 0);
  residuals_.setZero(num_pixels);

  forward_kinematics(model, q_, kinematics_);
  renderer.render(kinematics_, base_);
  // Pixels the robot at q covers and the image explains.
  for (int p = 0; p < num_pixels; ++p) {
    const double r = base_.depth_m[std::size_t(p)];
    const double z = likelihood.observed_depth_m(p);
    if (r > 0 && z > 0 && std::abs(z - r) < params_.inlier_sigmas * likelihood.noise_std_at_m(z))
      used_[std::size_t(p)] = 1;
  }
  for (int k = 0; k < m; ++k) {
    const int dof = dofs_[std::size_t(k)];
    const double h = model.joint_type(dof) == JointType::kPrismatic ? params_.prismatic_step_m
                                                                    : params_.revolute_step_rad;
    const double q0 = q_[dof];
    q_[dof] = q0 + h;
    forward_kinematics(model, q_, kinematics_);
    renderer.render(kinematics_, plus_);
    q_[dof] = q0 - h;
    forward_kinematics(model, q_, kinematics_);
    renderer.render(kinematics_, minus_);
    q_[dof] = q0;
    for (int p = 0; p < num_pixels; ++p) {
      if (!used_[std::size_t(p)]) continue;
      const float rp = plus_.depth_m[std::size_t(p)], rm = minus_.depth_m[std::size_t(p)];
      if (!(rp > 0 && rm > 0)) {  // on the silhouette: not differentiable here
        used_[std::size_t(p)] = 0;
        continue;
      }
      // A jump between surfaces (one link in front of another) is an edge too.
      const double r0 = base_.depth_m[std::size_t(p)];
      const double sigma = likelihood.noise_std_at_m(likelihood.observed_depth_m(p));
      if (std::abs(rp - r0) > params_.inlier_sigmas * sigma ||
          std::abs(rm - r0) > params_.inlier_sigmas * sigma) {
        used_[std::size_t(p)] = 0;
        continue;
      }
      gradients_(p, k) = float((rp - rm) / (2 * h) / sigma);
    }
  }
  pixels_used_ = 0;
  for (int p = 0; p < num_pixels; ++p) {
    if (used_[std::size_t(p)]) {
      ++pixels_used_;
      const double z = likelihood.observed_depth_m(p);
      residuals_[p] = float((z - base_.depth_m[std::size_t(p)]) / likelihood.noise_std_at_m(z));
    } else {
      gradients_.row(p).setZero();
    }
  }
  pixels_per_dof_.assign(std::size_t(m), 0);
  for (int k = 0; k < m; ++k)
    for (int p = 0; p < num_pixels; ++p) pixels_per_dof_[std::size_t(k)] += gradients_(p, k) != 0;
  information_.noalias() = (gradients_.transpose() * gradients_).cast<double>();
  gradient_.noalias() = (gradients_.transpose() * residuals_).cast<double>();
  estimate_effective_pixel_fraction(likelihood.width());
  return information_;
}

void ImageInformation::estimate_effective_pixel_fraction(int width) {
  const int num_pixels = int(used_.size());
  effective_pixel_fraction_ = 1;
  if (pixels_used_ == 0) return;
  double sum_sq = 0;
  for (int p = 0; p < num_pixels; ++p)
    if (used_[std::size_t(p)]) sum_sq += double(residuals_[p]) * residuals_[p];
  // Correlation of the residuals of used pixels `step` apart (1: the next
  // column, width: the next row), without removing the mean: a shared
  // offset is exactly the correlated part that must not count N times.
  auto neighbour_correlation = [&](int step, bool same_row) {
    double cross = 0, a2 = 0, b2 = 0;
    for (int p = 0; p + step < num_pixels; ++p) {
      if (same_row && (p % width) + step >= width) continue;
      if (!used_[std::size_t(p)] || !used_[std::size_t(p + step)]) continue;
      const double a = residuals_[p], b = residuals_[p + step];
      cross += a * b;
      a2 += a * a;
      b2 += b * b;
    }
    if (!(a2 > 0 && b2 > 0)) return 0.0;
    return std::clamp(cross / std::sqrt(a2 * b2), 0.0, 0.99);
  };
  const double rho_x = neighbour_correlation(1, true);
  const double rho_y = neighbour_correlation(width, false);
  const double mean_square = sum_sq / pixels_used_;
  effective_pixel_fraction_ =
      (1 - rho_x) / (1 + rho_x) * (1 - rho_y) / (1 + rho_y) / std::max(1.0, mean_square);
}

}  // namespace arttrack
