#include "arttrack/tracker/image_information.h"

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
  return information_;
}

}  // namespace arttrack
