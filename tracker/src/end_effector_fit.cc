#include "arttrack/tracker/internal/end_effector_fit.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace arttrack {
namespace {

// The nearest link with geometry at or above `link`, -1 when none or when
// the camera hangs below it (moving it would move the camera: that is the
// camera offset's to correct).
int fit_link_of(const RobotModel& model, int link) {
  const std::vector<int>& with_geometry = model.links_with_geometry();
  int found = -1;
  for (int a = link; a >= 0 && found < 0; a = model.link(a).parent)
    if (std::find(with_geometry.begin(), with_geometry.end(), a) != with_geometry.end()) found = a;
  for (int a = model.camera_link(); a >= 0 && found >= 0; a = model.link(a).parent)
    if (a == found) return -1;
  return found;
}

Eigen::Matrix3d rotation_of(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  return angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
                   : Eigen::Matrix3d::Identity();
}

}  // namespace

Eigen::Isometry3d correction_transform(const EndEffectorCorrection& c) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation_of(c.tail<3>());
  T.translation() = c.head<3>();
  return T;
}

bool rigid_fit_motion(const ImageInformation::RigidFit& fit, double max_var_m2,
                      Eigen::Isometry3d& motion, Eigen::Matrix3d& translation_noise_m2) {
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> normal(fit.information);
  if (fit.pixels == 0 || normal.info() != Eigen::Success || !(normal.vectorD().array() > 0).all())
    return false;
  const Eigen::Matrix<double, 6, 6> noise =
      normal.solve(Eigen::Matrix<double, 6, 6>::Identity());  // m^2, rad^2
  if (!(noise.diagonal().head<3>().maxCoeff() < max_var_m2)) return false;
  translation_noise_m2 = noise.topLeftCorner<3, 3>();
  const Eigen::Matrix<double, 6, 1> x = normal.solve(fit.gradient);
  motion.setIdentity();
  motion.linear() = rotation_of(x.tail<3>());
  motion.translation() = fit.origin_m + x.head<3>() - motion.linear() * fit.origin_m;
  return true;
}

EndEffectorFit::EndEffectorFit(const TrackerSetup& setup)
    : setup_(setup),
      estimates_(setup.ee_links.size()),
      scatter_m2_(setup.ee_links.size(), Eigen::Matrix3d::Zero()),
      fits_weight_(setup.ee_links.size(), 0.0),
      last_seen_s_(setup.ee_links.size(), 0.0),
      average_(setup.ee_links.size(), EndEffectorCorrection::Zero()),
      weak_shape_(setup.ee_links.size(), Eigen::Matrix3d::Zero()),
      link_scale_m2_(setup.ee_links.size(), Eigen::Matrix3d::Zero()),
      kinematics_(*setup.model),
      q_(Eigen::VectorXd::Zero(setup.n)) {
  const TrackerConfig& c = setup.config;
  if (c.method != TrackingMethod::kFullFusion || !c.end_effector_fit.enabled) return;
  time_constant_s_ = c.end_effector_fit.time_constant_s;
  max_var_m2_ = c.end_effector_fit.max_std_m * c.end_effector_fit.max_std_m;
  unpinned_scale_ = c.model_error_unpinned_scale;
  depth_scale_std_ = c.depth_scale_std;
  link_scales_ = c.end_effector_fit.link_scales;
  for (std::size_t e = 0; e < setup.ee_links.size(); ++e) {
    const int link = fit_link_of(*setup.model, setup.ee_links[e]);
    if (link < 0) continue;
    fit_links_.push_back(link);
    fitted_ee_.push_back(int(e));
  }
  on_ = !fit_links_.empty();
  motions_.assign(fit_links_.size(), Eigen::Isometry3d::Identity());
  seen_.assign(fit_links_.size(), false);
  noise_m2_.assign(fit_links_.size(), Eigen::Matrix3d::Zero());
  scale_shift_m2_.assign(fit_links_.size(), Eigen::Matrix3d::Zero());
}

Eigen::Matrix3d scale_shift_m2(const ImageInformation::RigidFit& fit,
                               std::span<const double> link_scales,
                               const Eigen::Vector3d& point_m) {
  Eigen::Matrix3d sum_m2 = Eigen::Matrix3d::Zero();
  if (link_scales.empty()) return sum_m2;
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> normal(fit.information);
  if (normal.info() != Eigen::Success) return sum_m2;
  for (int c = 0; c < fit.scale_cross.cols(); ++c) {
    const std::size_t link = std::size_t(fit.scale_links[std::size_t(c)]);
    const double scale = link < link_scales.size() ? link_scales[link] : 0.0;
    if (!std::isfinite(scale) || scale == 0) continue;
    // The motion a unit scale fits, X -> X + t + w x (X - o), at the point.
    const Eigen::Matrix<double, 6, 1> x = normal.solve(fit.scale_cross.col(c));
    const Eigen::Vector3d shift_m =
        scale * (x.head<3>() + x.tail<3>().cross(point_m - fit.origin_m));
    sum_m2.noalias() += shift_m * shift_m.transpose();
  }
  return sum_m2;
}

void EndEffectorFit::update(double time_s, const std::vector<ImageInformation::RigidFit>& fits,
                            std::span<const double> mean_fitted, std::span<const double> mean_final,
                            double model_error_std_m,
                            std::span<const Eigen::Vector3d> axis_shifts_m,
                            std::span<const double> link_scales) {
  if (!on_) return;
  const double dt = started_ ? std::max(0.0, time_s - last_time_s_) : 0.0;
  started_ = true;
  last_time_s_ = time_s;
  const double weight = 1 - std::exp(-dt / time_constant_s_);
  if (!(weight > 0)) return;
  // Each fit the image determines: the rigid motion it moves its subtree
  // by, X -> R (X - o) + o + t.
  bool any = false;
  for (std::size_t f = 0; f < fit_links_.size(); ++f) {
    seen_[f] = false;
    if (f >= fits.size()) continue;
    if (!rigid_fit_motion(fits[f], max_var_m2_, motions_[f], noise_m2_[f]))
      continue;  // the image barely shows it
    if (f < axis_shifts_m.size()) motions_[f].translation() += axis_shifts_m[f];
    seen_[f] = any = true;
  }
  // A held correction fades, and says less, the longer no image has shown
  // its hand: the kinematic error it stands for changes with the pose.
  for (std::size_t f = 0; f < fit_links_.size(); ++f) {
    const std::size_t e = ee_of(f);
    if (!seen_[f] && fits_weight_[e] > 0) {
      const double fade = std::exp(-(time_s - last_seen_s_[e]) / time_constant_s_);
      estimates_[e].weight = fits_weight_[e] * fade;
      estimates_[e].correction = fade * average_[e];
    }
  }
  if (!any) return;
  // Where the fitted mean's kinematics put each end effector, moved as the
  // image shows it; then relative to the final mean's (one kinematics each).
  const RobotModel& model = *setup_.model;
  for (int j = 0; j < setup_.n; ++j) q_[j] = mean_fitted[std::size_t(j)];
  forward_kinematics(model, q_, kinematics_);
  for (std::size_t f = 0; f < fit_links_.size(); ++f) {
    if (!seen_[f]) continue;
    const Eigen::Isometry3d T_camera_ee =
        T_camera_link(model, kinematics_, setup_.ee_links[ee_of(f)]);
    if (link_scales_)
      scale_shift_m2_[f] = scale_shift_m2(fits[f], link_scales, T_camera_ee.translation());
    motions_[f] = motions_[f] * T_camera_ee;
  }
  for (int j = 0; j < setup_.n; ++j) q_[j] = mean_final[std::size_t(j)];
  forward_kinematics(model, q_, kinematics_);
  for (std::size_t f = 0; f < fit_links_.size(); ++f) {
    if (!seen_[f]) continue;
    const Eigen::Isometry3d T_camera_ee =
        T_camera_link(model, kinematics_, setup_.ee_links[ee_of(f)]);
    const Eigen::Isometry3d relative = T_camera_ee.inverse() * motions_[f];
    EndEffectorCorrection sample;
    const Eigen::AngleAxisd turn(relative.linear());
    sample << relative.translation(), turn.angle() * turn.axis();
    const std::size_t i = ee_of(f);
    EndEffectorFitEstimate& e = estimates_[i];
    // The exponentially weighted scatter about the average (West's update:
    // the deviation from the average before this sample), then the average.
    EndEffectorCorrection& average = average_[i];
    const EndEffectorCorrection deviation = sample - average;
    Eigen::Matrix3d& scatter = scatter_m2_[i];
    scatter =
        (1 - weight) * (scatter + weight * deviation.head<3>() * deviation.head<3>().transpose());
    average += weight * deviation;
    e.correction = average;
    // The noise's shape in end-effector axes (largest eigenvalue 1), averaged.
    const Eigen::Matrix3d R = T_camera_ee.linear();
    const Eigen::Matrix3d noise_ee_m2 = R.transpose() * noise_m2_[f] * R;
    const double largest_m2 =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(noise_ee_m2, Eigen::EigenvaluesOnly)
            .eigenvalues()[2];
    Eigen::Matrix3d& shape = weak_shape_[i];
    if (largest_m2 > 0) shape += weight * (noise_ee_m2 / largest_m2 - shape);
    Eigen::Matrix3d& link_scale = link_scale_m2_[i];
    if (link_scales_) link_scale += weight * (R.transpose() * scale_shift_m2_[f] * R - link_scale);
    double& total = fits_weight_[i];
    total += weight * (1 - total);
    e.weight = total;
    last_seen_s_[i] = time_s;
    const double shape_var_m2 = model_error_std_m * model_error_std_m;
    const Eigen::Vector3d scale_m = depth_scale_std_ * (R.transpose() * motions_[f].translation());
    e.position_covariance_m2 =
        scatter / total + shape_var_m2 * Eigen::Matrix3d::Identity() +
        (unpinned_scale_ * unpinned_scale_ - 1) * shape_var_m2 * (shape / total) +
        scale_m * scale_m.transpose() + link_scale / total;
  }
}

}  // namespace arttrack
