#include "arttrack/tracker/internal/estimate_report.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "arttrack/tracker/error.h"

namespace arttrack {

EstimateReport::EstimateReport(const TrackerSetup& setup)
    : setup_(setup), kinematics_(*setup.model), q_(Eigen::VectorXd::Zero(setup.n)) {}

void EstimateReport::fill(const JointBelief& belief, std::span<const double> readings_rad,
                          double time_s, const PosteriorCovariance& cov,
                          std::span<const double> mean_lag_var,
                          std::span<const EndEffectorFitEstimate> fits, TrackerEstimate& e) {
  const TrackerSetup& s = setup_;
  const RobotModel& model = *s.model;
  e.time_s = time_s;
  e.joint_names.assign(model.joint_names().begin(), model.joint_names().begin() + s.n_phys);
  e.angle_rad.resize(s.n_phys);
  e.angle_std_rad.resize(s.n_phys);
  e.bias_rad.resize(s.n_phys);
  e.bias_std_rad.resize(s.n_phys);
  const bool raw = s.config.method == TrackingMethod::kEncodersOnly;
  const auto var_q = s.filter_model->encoder_var_rad2();
  // Encoders only: the reading, off by a bias it does not estimate (bias
  // std 0), which the bias prior's stationary variance describes.
  // Otherwise, until the full covariance below says more: the filter's angle
  // variance, but never below the encoder's noise. An image's fold-back
  // leaves the moments of collapsed particles (about 0) in the filter, and a
  // joint whose bias is fixed (the dual-arm head) then claimed 1e-10 rad
  // against a 1 mrad error: its truth lay within 2 sigma in 0% of samples.
  const auto var_b0 = s.filter_model->initial_var_b();
  for (int j = 0; j < s.n_phys; ++j) {
    e.angle_rad[j] = raw ? readings_rad[j] : belief.mean_a[j];
    e.angle_std_rad[j] =
        std::sqrt(raw ? var_q[j] + var_b0[j] : std::max(belief.var_a[j], var_q[j]));
    e.bias_rad[j] = raw ? 0.0 : belief.mean_b[j];
    e.bias_std_rad[j] = raw ? 0.0 : std::sqrt(std::max(0.0, belief.var_b[j]));
  }
  for (int k = 0; k < 6; ++k) {
    const int j = s.n_phys + k;
    e.camera_offset[k] = raw ? 0.0 : belief.mean_a[j];
    e.camera_offset_std[k] = raw ? 0.0 : std::sqrt(belief.var_a[j]);
  }
  // After the first image, the DOFs the images inform report the full
  // covariance's marginals (posterior_covariance.h), predicted to now.
  Eigen::MatrixXd& angle_cov = angle_cov_;
  if (cov.started()) {
    cov.angle_covariance_at(std::max(cov.time_s(), time_s), angle_cov);
    ARTTRACK_CHECK_ARGUMENT(mean_lag_var.empty() || int(mean_lag_var.size()) == cov.size());
    for (std::size_t i = 0; i < mean_lag_var.size(); ++i)
      angle_cov(Eigen::Index(i), Eigen::Index(i)) += mean_lag_var[i];
    for (int i = 0; i < cov.size(); ++i) {
      const PosteriorCovariance::State& st = cov.states()[std::size_t(i)];
      const double var = std::max(0.0, angle_cov(i, i));
      if (st.kind == PosteriorCovariance::Kind::kBias) {
        e.bias_std_rad[st.dof] = std::sqrt(var);
        angle_cov(i, i) = var + var_q[st.dof];  // a = q - b: plus the encoder's noise
        e.angle_std_rad[st.dof] = std::sqrt(angle_cov(i, i));
      } else if (st.dof < s.n_phys) {
        e.angle_std_rad[st.dof] = std::sqrt(var);
      } else {
        e.camera_offset_std[st.dof - s.n_phys] = std::sqrt(var);
      }
    }
  }
  for (int j = 0; j < s.n_phys; ++j) q_[j] = e.angle_rad[j];
  for (int k = 0; k < 6; ++k) q_[s.n_phys + k] = e.camera_offset[k];
  forward_kinematics(model, q_, kinematics_);
  e.T_camera_ee.clear();  // `e` may hold an earlier estimate (Tracker::estimate(out))
  for (int link : s.ee_links) e.T_camera_ee.push_back(T_camera_link(model, kinematics_, link));
  // End-effector covariance: J C J^T, C the DOFs' covariance: independent
  // (their reported variances), but where the full covariance knows better.
  Eigen::MatrixXd& dof_cov = dof_cov_;
  dof_cov.setZero(s.n, s.n);
  for (int j = 0; j < s.n; ++j) {
    const double sd = j < s.n_phys ? e.angle_std_rad[j] : e.camera_offset_std[j - s.n_phys];
    dof_cov(j, j) = sd * sd;
  }
  if (cov.started()) {
    for (int a = 0; a < cov.size(); ++a)
      for (int b = 0; b < cov.size(); ++b)
        dof_cov(cov.states()[std::size_t(a)].dof, cov.states()[std::size_t(b)].dof) =
            angle_cov(a, b);
  }
  e.T_camera_ee_covariance.clear();
  for (int link : s.ee_links) {
    camera_link_jacobian(model, kinematics_, link, jacobian_);
    jacobian_cov_.noalias() = jacobian_ * dof_cov;
    e.T_camera_ee_covariance.emplace_back();
    e.T_camera_ee_covariance.back().noalias() = jacobian_cov_ * jacobian_.transpose();
  }
  e.ee_image_correction.assign(s.ee_links.size(), EndEffectorCorrection::Zero());
  for (std::size_t k = 0; k < fits.size() && k < s.ee_links.size(); ++k) {
    const EndEffectorFitEstimate& fit = fits[k];
    e.ee_image_correction[k] = fit.correction;
    // The reported position is (1 - a) of the kinematics' plus a of the
    // fits' (a their weight), the two errors independent: the position
    // block (1 - a)^2 C + a^2 F, its cross terms (1 - a) C; the rotation's
    // stays the kinematics' (the hand's shape error turns the fit by
    // what no pixel noise says).
    const double a = fit.weight;
    if (a > 0) {
      const Eigen::Matrix3d R = e.T_camera_ee[k].linear();
      Eigen::Matrix<double, 6, 6>& C = e.T_camera_ee_covariance[k];
      C.topLeftCorner<3, 3>() = (1 - a) * (1 - a) * C.topLeftCorner<3, 3>() +
                                a * a * (R * fit.position_covariance_m2 * R.transpose());
      C.topRightCorner<3, 3>() *= 1 - a;
      C.bottomLeftCorner<3, 3>() *= 1 - a;
    }
    e.T_camera_ee[k] = e.T_camera_ee[k] * correction_transform(fit.correction);
  }
}

}  // namespace arttrack
