#include "arttrack/tracker/posterior_covariance.h"

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

}  // namespace

PosteriorCovariance::PosteriorCovariance(std::vector<State> states) : states_(std::move(states)) {
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
}

void PosteriorCovariance::reset(const Eigen::VectorXd& variances, double time_s) {
  if (variances.size() != size())
    throw InputError("posterior covariance: " + std::to_string(variances.size()) +
                     " variances for " + std::to_string(size()) + " states");
  P_ = variances.cwiseMax(0.0).asDiagonal();
  time_s_ = time_s;
  started_ = true;
}

void PosteriorCovariance::restart_state(int i, double variance) {
  P_.row(i).setZero();
  P_.col(i).setZero();
  P_(i, i) = std::max(0.0, variance);
}

void PosteriorCovariance::predict_to(double time_s) {
  const double dt = time_s - time_s_;
  if (!(dt >= 0)) throw InputError("posterior covariance: predicted backwards in time");
  const int m = size();
  for (int i = 0; i < m; ++i) {
    double phi_i, added;
    transition(states_[std::size_t(i)], dt, phi_i, added);
    P_.row(i) *= phi_i;
    P_.col(i) *= phi_i;
    P_(i, i) += added;
  }
  time_s_ = time_s;
}

void PosteriorCovariance::update(const Eigen::MatrixXd& angle_information,
                                 double information_scale) {
  if (angle_information.rows() != size() || angle_information.cols() != size())
    throw InputError("posterior covariance: information matrix of the wrong size");
  // Id + P s D I D, solved against P: (P^-1 + s D I D)^-1 without inverting P.
  scratch_.noalias() = P_ * (sign_.asDiagonal() * angle_information * sign_.asDiagonal());
  scratch_ *= information_scale;
  scratch_ += identity_;
  P_ = scratch_.partialPivLu().solve(P_);
  P_ = 0.5 * (P_ + P_.transpose()).eval();
}

double PosteriorCovariance::variance_at(int i, double time_s) const {
  double phi, added;
  transition(states_[std::size_t(i)], std::max(0.0, time_s - time_s_), phi, added);
  return phi * phi * P_(i, i) + added;
}

Eigen::MatrixXd PosteriorCovariance::angle_covariance() const {
  return sign_.asDiagonal() * P_ * sign_.asDiagonal();
}

}  // namespace arttrack
