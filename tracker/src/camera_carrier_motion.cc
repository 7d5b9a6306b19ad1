#include "arttrack/tracker/internal/camera_carrier_motion.h"

#include <algorithm>
#include <cmath>

#include "arttrack/tracker/error.h"

namespace arttrack {

CameraCarrierMotion::CameraCarrierMotion(const RobotModel& model, const JointFilterModel& filters,
                                         const TrackerConfig& config)
    : rate_var_(std::size_t(model.num_joints()), 0.0) {
  const int camera = model.nominal_camera_link();
  int virtual_seen = 0;
  for (int dof = 0; dof < model.num_joints(); ++dof) {
    if (model.is_virtual_joint(dof)) {
      const VirtualJointParams& p = config.camera_joint_params(virtual_seen++);
      rate_var_[std::size_t(dof)] =
          p.motion_diffusion_per_sqrt_rad * p.motion_diffusion_per_sqrt_rad;
    } else if (model.links_moved_by(dof)[std::size_t(camera)]) {
      carrying_dofs_.push_back(dof);
      noise_allowance_.push_back(std::sqrt(2 * filters.encoder_var_rad2()[std::size_t(dof)]));
    }
  }
  previous_.assign(carrying_dofs_.size(), 0.0);
  // Vision only has no encoder: its head angles come from the images, as
  // the offset does, and their image-to-image jitter is no measure of how
  // far the head turned (with it, occlusion__constant_bias seed 3 lost
  // the arm before the panel came).
  on_ = config.method != TrackingMethod::kVisionOnly && !carrying_dofs_.empty() &&
        std::any_of(rate_var_.begin(), rate_var_.end(), [](double v) { return v > 0; });
}

double CameraCarrierMotion::added_variance(std::span<const double> mean_a,
                                           std::span<double> added_var) {
  if (mean_a.size() != rate_var_.size() || added_var.size() != rate_var_.size())
    throw InputError("camera carrier motion: expected " + std::to_string(rate_var_.size()) +
                     " DOFs, got " + std::to_string(mean_a.size()) + " and " +
                     std::to_string(added_var.size()));
  double travel = 0;
  for (std::size_t k = 0; k < carrying_dofs_.size(); ++k) {
    const double q = mean_a[std::size_t(carrying_dofs_[k])];
    if (started_) travel += std::max(0.0, std::abs(q - previous_[k]) - noise_allowance_[k]);
    previous_[k] = q;
  }
  started_ = true;
  for (std::size_t j = 0; j < rate_var_.size(); ++j) added_var[j] = rate_var_[j] * travel;
  return travel;
}

}  // namespace arttrack
