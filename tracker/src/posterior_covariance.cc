#include "arttrack/tracker/internal/posterior_covariance.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

// Over dt: the factor on a state's deviation and the variance its noise adds.
void transition(const PosteriorCovariance::State& s, double dt_s, double& phi, double& added) {
  if (s.decay_per_s > 0) {
    phi = std::exp(-s.decay_per_s * dt_s);
    added = s.rate_var * (1 - phi * phi) / (2 * s.decay_per_s);
  } else {
    phi = 1;
    added = s.rate_var * dt_s;
  }
}

// A covariance over `states` moved on by dt_s >= 0 (else InputError): each
// state's row and column times its phi, in state order, plus the variance
// its noise adds. predict_to() and angle_covariance_at() share it, so they
// agree to the bit.
void predict_covariance(const std::vector<PosteriorCovariance::State>& states, double dt_s,
                        Eigen::MatrixXd& M) {
  if (!(dt_s >= 0)) throw InputError("posterior covariance: predicted backwards in time");
  for (int i = 0; i < int(states.size()); ++i) {
    double phi, added;
    transition(states[std::size_t(i)], dt_s, phi, added);
    M.row(i) *= phi;
    M.col(i) *= phi;
    M(i, i) += added;
  }
}

// out = (M + M^T) / 2, without a temporary (`out` must not be M).
void symmetrise(const Eigen::MatrixXd& M, Eigen::MatrixXd& out) { out = 0.5 * (M + M.transpose()); }

}  // namespace

PosteriorCovariance::PosteriorCovariance(std::vector<State> states, int num_consider)
    : states_(std::move(states)), num_consider_(num_consider) {
  if (num_consider < 0)
    throw InputError("posterior covariance: negative number of consider parameters");
  const int m = size();
  sign_.resize(m);
  for (int i = 0; i < m; ++i) {
    const State& s = states_[std::size_t(i)];
    if (!(s.decay_per_s >= 0) || !(s.rate_var >= 0) || !std::isfinite(s.decay_per_s) ||
        !std::isfinite(s.rate_var))
      throw InputError("posterior covariance: state " + std::to_string(i) +
                       " has a negative or non-finite decay or diffusion");
    sign_[i] = s.kind == Kind::kBias ? -1.0 : 1.0;
  }
  P_ = Eigen::MatrixXd::Zero(m, m);
  scratch_ = Eigen::MatrixXd::Zero(m, m);
  identity_ = Eigen::MatrixXd::Identity(m, m);
  J_ = Eigen::MatrixXd::Zero(m, m);
  lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(m);
  if (num_consider_ > 0) {
    Q_ee_ = A_ = PJ_ = Eigen::MatrixXd::Zero(m, m);
    Q_ec_ = B_ = B_widened_ = AQ_ = signed_cross_ = Eigen::MatrixXd::Zero(m, num_consider_);
  }
}

void PosteriorCovariance::reset(const Eigen::VectorXd& variances, double time_s) {
  if (variances.size() != size())
    throw InputError("posterior covariance: " + std::to_string(variances.size()) +
                     " variances for " + std::to_string(size()) + " states");
  P_ = variances.cwiseMax(0.0).asDiagonal();
  if (num_consider_ > 0) {
    Q_ee_ = P_;
    Q_ec_.setZero();
  }
  time_s_ = time_s;
  started_ = true;
}

void PosteriorCovariance::restart_state(int i, double variance) {
  P_.row(i).setZero();
  P_.col(i).setZero();
  P_(i, i) = std::max(0.0, variance);
  if (num_consider_ > 0) {
    Q_ee_.row(i).setZero();
    Q_ee_.col(i).setZero();
    Q_ee_(i, i) = P_(i, i);
    Q_ec_.row(i).setZero();
  }
}

void PosteriorCovariance::predict_to(double time_s) {
  const double dt = time_s - time_s_;
  predict_covariance(states_, dt, P_);
  if (num_consider_ > 0) {
    predict_covariance(states_, dt, Q_ee_);
    for (int i = 0; i < size(); ++i) {  // the error's correlation with the parameters
      double phi_i, added;
      transition(states_[std::size_t(i)], dt, phi_i, added);
      Q_ec_.row(i) *= phi_i;
    }
  }
  time_s_ = time_s;
}

void PosteriorCovariance::add_variance(int i, double variance) {
  if (i < 0 || i >= size() || !(variance >= 0) || !std::isfinite(variance))
    throw InputError("posterior covariance: bad added variance for state " + std::to_string(i));
  P_(i, i) += variance;
  if (num_consider_ > 0) Q_ee_(i, i) += variance;
}

void PosteriorCovariance::update(const Eigen::MatrixXd& angle_information,
                                 double information_scale) {
  update(angle_information, nullptr, nullptr, nullptr, information_scale, 1.0);
}

void PosteriorCovariance::update(const Eigen::MatrixXd& angle_information,
                                 const Eigen::MatrixXd& consider_cross, double information_scale,
                                 double noise_scale) {
  update(angle_information, &consider_cross, nullptr, nullptr, information_scale, noise_scale);
}

void PosteriorCovariance::update(const Eigen::MatrixXd& angle_information,
                                 const Eigen::MatrixXd& consider_cross,
                                 const Eigen::MatrixXd& widened_cross,
                                 const std::vector<char>& widened, double information_scale,
                                 double noise_scale) {
  update(angle_information, &consider_cross, &widened_cross, &widened, information_scale,
         noise_scale);
}

void PosteriorCovariance::update(const Eigen::MatrixXd& angle_information,
                                 const Eigen::MatrixXd* consider_cross,
                                 const Eigen::MatrixXd* widened_cross,
                                 const std::vector<char>* widened, double information_scale,
                                 double noise_scale) {
  if (!(noise_scale >= 0 && noise_scale <= 1))
    throw InputError("posterior covariance: noise scale " + std::to_string(noise_scale) +
                     " is not in [0, 1]");
  auto check = [&](const Eigen::MatrixXd& m, int cols, const char* what) {
    if (m.rows() != size() || m.cols() != cols)
      throw InputError(std::string("posterior covariance: ") + what + " is " +
                       std::to_string(m.rows()) + " x " + std::to_string(m.cols()) + ", not " +
                       std::to_string(size()) + " x " + std::to_string(cols));
  };
  check(angle_information, size(), "the information matrix");
  if (consider_cross) check(*consider_cross, num_consider_, "the consider cross-information");
  if (widened_cross) check(*widened_cross, num_consider_, "the widened cross-information");
  if (widened && int(widened->size()) != size())
    throw InputError("posterior covariance: " + std::to_string(widened->size()) +
                     " widened flags, not one per state (" + std::to_string(size()) + ")");
  update_nominal(angle_information, information_scale);
  if (num_consider_ > 0)
    propagate_error(consider_cross, information_scale, widened_cross, widened, noise_scale);
}

void PosteriorCovariance::update_nominal(const Eigen::MatrixXd& angle_information,
                                         double information_scale) {
  // Id + P s D I D, solved against P: (P^-1 + s D I D)^-1 without inverting P.
  J_.noalias() = sign_.asDiagonal() * angle_information * sign_.asDiagonal();
  scratch_.noalias() = P_ * J_;
  scratch_ *= information_scale;
  scratch_ += identity_;
  J_ *= information_scale;  // J_xx, for propagate_error()
  lu_.compute(scratch_);    // into its sized storage: no allocation
  scratch_.noalias() = lu_.solve(P_);
  symmetrise(scratch_, P_);
}

// The error's covariance after the update that gave P_ (P+), with J_ = J_xx.
void PosteriorCovariance::propagate_error(const Eigen::MatrixXd* consider_cross,
                                          double information_scale,
                                          const Eigen::MatrixXd* widened_cross,
                                          const std::vector<char>* widened, double noise_scale) {
  PJ_.noalias() = P_ * J_;  // P+ J_xx
  A_ = identity_ - PJ_;
  if (consider_cross) {
    signed_cross_.noalias() = sign_.asDiagonal() * *consider_cross;
    B_.noalias() = P_ * signed_cross_;
    B_ *= -information_scale;
    if (widened_cross) {
      signed_cross_.noalias() = sign_.asDiagonal() * *widened_cross;
      B_widened_.noalias() = P_ * signed_cross_;
      B_widened_ *= -information_scale;
      for (int i = 0; i < size(); ++i)
        if ((*widened)[std::size_t(i)]) B_.row(i) = B_widened_.row(i);
    }
  } else {
    B_.setZero();
  }
  // Q_ee <- A Q_ee A^T + A Q_ec B^T + B Q_ce A^T + B B^T + P+ J_xx P+.
  scratch_.noalias() = A_ * Q_ee_;
  Q_ee_.noalias() = scratch_ * A_.transpose();
  AQ_.noalias() = A_ * Q_ec_;  // m x c
  scratch_.noalias() = AQ_ * B_.transpose();
  Q_ee_ += scratch_ + scratch_.transpose();
  Q_ee_.noalias() += B_ * B_.transpose();
  if (noise_scale == 1) {
    Q_ee_.noalias() += PJ_ * P_;
  } else {  // the pixels' noise as the image's fitted residuals size it
    scratch_.noalias() = PJ_ * P_;
    Q_ee_ += noise_scale * scratch_;
  }
  scratch_ = Q_ee_;
  symmetrise(scratch_, Q_ee_);
  // Q_ec <- A Q_ec + B.
  Q_ec_ = AQ_ + B_;
}

double PosteriorCovariance::variance_at(int i, double time_s) const {
  double phi, added;
  transition(states_[std::size_t(i)], std::max(0.0, time_s - time_s_), phi, added);
  return phi * phi * reported()(i, i) + added;
}

Eigen::MatrixXd PosteriorCovariance::covariance() const { return reported(); }

Eigen::MatrixXd PosteriorCovariance::angle_covariance() const {
  Eigen::MatrixXd out;
  angle_covariance(out);
  return out;
}

void PosteriorCovariance::angle_covariance(Eigen::MatrixXd& out) const {
  out = sign_.asDiagonal() * reported() * sign_.asDiagonal();
}

void PosteriorCovariance::angle_covariance_at(double time_s, Eigen::MatrixXd& out) const {
  angle_covariance(out);
  // predict_to()'s operations: D's signs commute with them exactly.
  predict_covariance(states_, time_s - time_s_, out);
}

void PosteriorCovariance::nominal_angle_covariance(Eigen::MatrixXd& out) const {
  out = sign_.asDiagonal() * P_ * sign_.asDiagonal();
}

}  // namespace arttrack
