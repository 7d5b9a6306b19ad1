#include "arttrack/tracker/internal/joint_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/units.h"
#include "config_range.h"

namespace arttrack {
namespace {

// The bias transition over dt for decay rate k: the mean factor
// phi = exp(-k dt) = c^dt, and the variance an Ornstein-Uhlenbeck process of
// unit diffusion rate gains, (1 - exp(-2 k dt)) / (2 k) (dt for k -> 0, a
// plain random walk). Recomputed only when k changes from one joint to the
// next: joints usually share their parameters, and the exps dominate a step.
struct BiasTransition {
  double dt = 0;
  double k = std::numeric_limits<double>::quiet_NaN();
  double phi = 1;
  double var_per_rate = 0;

  explicit BiasTransition(double dt_s) : dt(dt_s) {}
  void set(double k_j) {
    if (k_j == k) return;
    k = k_j;
    phi = std::exp(-k * dt);
    const double x = 2 * k * dt;
    // (1 - e^-x) / x = 1 - x/2 + x^2/6 - ...; below 1e-8 the x^2 term is
    // under the rounding of the result.
    var_per_rate = x < 1e-8 ? dt * (1 - 0.5 * x) : -std::expm1(-x) / (2 * k);
  }
};

void check_finite_readings(const JointFilterModel& model, std::span<const double> q) {
  if (int(q.size()) != model.num_encoder_joints()) {
    throw InputError("joint filter: got " + std::to_string(q.size()) +
                     " encoder readings, expected " + std::to_string(model.num_encoder_joints()));
  }
  for (size_t j = 0; j < q.size(); ++j) {
    if (!std::isfinite(q[j])) {
      throw InputError("joint filter: non-finite encoder reading for joint '" +
                       model.joint_names()[j] + "'");
    }
  }
}

void check_dt(double dt_s) {
  if (!(dt_s >= 0) || !std::isfinite(dt_s)) {
    throw InputError("joint filter: time step " + std::to_string(dt_s) +
                     " s is negative or not finite (time stamps out of order?)");
  }
}

// The prediction of joint j over the transition `bias` (paper Eqs. (4) and
// (5)): the angle's random walk, the bias's Ornstein-Uhlenbeck decay.
inline void predict_one(const BiasTransition& bias, double dt_s, double rate_a, double rate_b,
                        double& mb, double& paa, double& pab, double& pbb) {
  mb *= bias.phi;
  paa += rate_a * dt_s;
  pab *= bias.phi;
  pbb = bias.phi * bias.phi * pbb + rate_b * bias.var_per_rate;
}

// One Kalman measurement update of joint j with reading q, H = [1 1],
// Joseph form P' = (I - K H) P (I - K H)^T + R K K^T: a sum of two positive
// semi-definite terms, so the covariance stays PSD under rounding.
inline void update_one(double q, double r, double& a, double& b, double& paa, double& pab,
                       double& pbb) {
  const double ga = paa + pab;  // P H^T
  const double gb = pab + pbb;
  const double s = ga + gb + r;  // H P H^T + R
  const double inv_s = 1 / s;
  const double ka = ga * inv_s;
  const double kb = gb * inv_s;
  const double innovation = q - a - b;
  a += ka * innovation;
  b += kb * innovation;
  // M = (I - K H) P, then P' = M (I - K H)^T + R K K^T.
  const double m00 = (1 - ka) * paa - ka * pab;
  const double m01 = (1 - ka) * pab - ka * pbb;
  const double m10 = -kb * paa + (1 - kb) * pab;
  const double m11 = -kb * pab + (1 - kb) * pbb;
  const double n00 = m00 * (1 - ka) - m01 * ka + r * ka * ka;
  const double n01 = -m00 * kb + m01 * (1 - kb) + r * ka * kb;
  const double n11 = -m10 * kb + m11 * (1 - kb) + r * kb * kb;
  paa = n00;
  pab = n01;
  pbb = n11;
}

}  // namespace

double JointFilterParams::stationary_bias_std_rad() const {
  if (!estimate_bias) return 0;
  return bias_diffusion_rad_per_sqrt_s / std::sqrt(2 * std::log(1 / bias_decay_per_s));
}

void JointFilterParams::validate(std::string_view source, const std::string& prefix,
                                 bool linear) const {
  const JointNoiseKeys& keys = joint_noise_keys(linear);
  check_range(source, prefix + keys.encoder_noise, encoder_noise_rad,
              ConfigRange::open_closed(0, keys.max_encoder_noise), keys.unit);
  check_range(source, prefix + keys.motion_diffusion, angle_diffusion_rad_per_sqrt_s,
              ConfigRange::closed(0, keys.max_diffusion), keys.unit);
  // sigma_b and c matter only while the bias is estimated; c is held to
  // (0, 1) either way, so that a per-joint override that switches the
  // estimate on never inherits an impossible decay.
  ConfigRange sigma_b = ConfigRange::closed(0, keys.max_diffusion);
  sigma_b.lo_open = estimate_bias;
  check_range(source, prefix + keys.bias_diffusion, bias_diffusion_rad_per_sqrt_s, sigma_b,
              keys.unit);
  check_range(source, prefix + "bias_decay_per_s", bias_decay_per_s, ConfigRange::open(0, 1));
}

JointFilterOverride JointFilterOverride::all_of(const JointFilterParams& p) {
  return {p.encoder_noise_rad,
          p.angle_diffusion_rad_per_sqrt_s,
          p.bias_diffusion_rad_per_sqrt_s,
          p.bias_decay_per_s,
          p.estimate_bias,
          false};
}

JointFilterParams JointFilterOverride::over(JointFilterParams p) const {
  p.encoder_noise_rad = encoder_noise.value_or(p.encoder_noise_rad);
  p.angle_diffusion_rad_per_sqrt_s =
      motion_diffusion_per_sqrt_s.value_or(p.angle_diffusion_rad_per_sqrt_s);
  p.bias_diffusion_rad_per_sqrt_s =
      bias_diffusion_per_sqrt_s.value_or(p.bias_diffusion_rad_per_sqrt_s);
  p.bias_decay_per_s = bias_decay_per_s.value_or(p.bias_decay_per_s);
  p.estimate_bias = estimate_bias.value_or(p.estimate_bias);
  return p;
}

JointFilterModel::JointFilterModel(std::vector<std::string> encoder_joints,
                                   std::vector<JointFilterParams> encoder_params,
                                   std::vector<std::string> virtual_joints,
                                   std::vector<VirtualJointParams> virtual_params) {
  if (encoder_joints.size() != encoder_params.size() ||
      virtual_joints.size() != virtual_params.size()) {
    throw InputError("joint filter: " + std::to_string(encoder_joints.size()) + " joints but " +
                     std::to_string(encoder_params.size()) +
                     " parameter sets (virtual: " + std::to_string(virtual_joints.size()) + " vs " +
                     std::to_string(virtual_params.size()) + ")");
  }
  num_encoder_ = int(encoder_joints.size());
  names_ = std::move(encoder_joints);
  names_.insert(names_.end(), virtual_joints.begin(), virtual_joints.end());
  for (size_t i = 0; i < names_.size(); ++i) {
    if (std::find(names_.begin(), names_.begin() + i, names_[i]) != names_.begin() + i) {
      throw InputError("joint filter: joint '" + names_[i] + "' listed twice");
    }
  }
  auto bad = [&](const std::string& joint, const char* field, double value) {
    return InputError("joint filter: joint '" + joint + "': " + field + " = " +
                      std::to_string(value) + " is out of range");
  };
  for (int j = 0; j < num_encoder_; ++j) {
    const JointFilterParams& p = encoder_params[j];
    p.validate("joint filter: joint '" + names_[j] + "'");
    var_q_.push_back(p.encoder_noise_rad * p.encoder_noise_rad);
    rate_a_.push_back(p.angle_diffusion_rad_per_sqrt_s * p.angle_diffusion_rad_per_sqrt_s);
    if (p.estimate_bias) {
      const double k = std::log(1 / p.bias_decay_per_s);
      const double rate_b = p.bias_diffusion_rad_per_sqrt_s * p.bias_diffusion_rad_per_sqrt_s;
      rate_b_.push_back(rate_b);
      k_.push_back(k);
      init_var_b_.push_back(rate_b / (2 * k));
    } else {
      rate_b_.push_back(0);
      k_.push_back(0);
      init_var_b_.push_back(0);
    }
    init_var_a_.push_back(0);  // set from the first reading
  }
  for (size_t v = 0; v < virtual_params.size(); ++v) {
    const VirtualJointParams& p = virtual_params[v];
    const std::string& n = names_[num_encoder_ + v];
    if (!(p.diffusion_per_sqrt_s >= 0) || !std::isfinite(p.diffusion_per_sqrt_s))
      throw bad(n, "diffusion_per_sqrt_s (must be >= 0)", p.diffusion_per_sqrt_s);
    if (!(p.initial_std > 0) || !std::isfinite(p.initial_std))
      throw bad(n, "initial_std (must be > 0)", p.initial_std);
    var_q_.push_back(0);  // no encoder
    rate_a_.push_back(p.diffusion_per_sqrt_s * p.diffusion_per_sqrt_s);
    rate_b_.push_back(0);
    k_.push_back(0);
    init_var_a_.push_back(p.initial_std * p.initial_std);
    init_var_b_.push_back(0);
  }
}

int JointFilterModel::index_of(std::string_view name) const {
  for (size_t j = 0; j < names_.size(); ++j) {
    if (names_[j] == name) return int(j);
  }
  return -1;
}

void JointFilterModel::set_encoder_var(int j, double var_rad2) {
  if (j < 0 || j >= num_encoder_)
    throw InputError("joint filter: no encoder joint " + std::to_string(j) + " of " +
                     std::to_string(num_encoder_));
  if (!(std::isfinite(var_rad2) && var_rad2 > 0))
    throw InputError("joint filter: " + names_[std::size_t(j)] + ": encoder variance " +
                     std::to_string(var_rad2) + " is not finite and positive");
  var_q_[std::size_t(j)] = var_rad2;
}

void JointBelief::set_joint(int j, const AngleBiasGaussian& g) {
  mean_a[j] = g.mean_a;
  mean_b[j] = g.mean_b;
  var_a[j] = g.var_a;
  cov_ab[j] = g.cov_ab;
  var_b[j] = g.var_b;
}

JointBelief initial_joint_belief(const JointFilterModel& model,
                                 std::span<const double> encoder_rad) {
  check_finite_readings(model, encoder_rad);
  const int n = model.num_joints();
  JointBelief b;
  b.mean_a.assign(n, 0);
  b.mean_b.assign(n, 0);
  b.var_a.assign(n, 0);
  b.cov_ab.assign(n, 0);
  b.var_b.assign(n, 0);
  for (int j = 0; j < n; ++j) {
    const double vb = model.initial_var_b()[j];
    if (j < model.num_encoder_joints()) {
      // a = q - b - e with b ~ N(0, vb), e ~ N(0, sigma_q^2) and a flat prior.
      b.mean_a[j] = encoder_rad[j];
      b.var_a[j] = model.encoder_var_rad2()[j] + vb;
      b.cov_ab[j] = -vb;
      b.var_b[j] = vb;
    } else {
      b.var_a[j] = model.initial_var_a()[j];
    }
  }
  return b;
}

void predict_joints(const JointFilterModel& model, double dt_s, JointBelief& belief) {
  check_dt(dt_s);
  ARTTRACK_CHECK_ARGUMENT(belief.size() == model.num_joints());
  const int n = model.num_joints();
  const double* rate_a = model.angle_rate_var().data();
  const double* rate_b = model.bias_rate_var().data();
  const double* k = model.bias_decay_rate_per_s().data();
  double* mb = belief.mean_b.data();
  double* paa = belief.var_a.data();
  double* pab = belief.cov_ab.data();
  double* pbb = belief.var_b.data();
  BiasTransition bias(dt_s);
  for (int j = 0; j < n; ++j) {
    bias.set(k[j]);
    predict_one(bias, dt_s, rate_a[j], rate_b[j], mb[j], paa[j], pab[j], pbb[j]);
  }
}

void update_encoders(const JointFilterModel& model, std::span<const double> encoder_rad,
                     JointBelief& belief) {
  check_finite_readings(model, encoder_rad);
  ARTTRACK_CHECK_ARGUMENT(belief.size() == model.num_joints());
  const double* r = model.encoder_var_rad2().data();
  for (int j = 0; j < model.num_encoder_joints(); ++j) {
    update_one(encoder_rad[j], r[j], belief.mean_a[j], belief.mean_b[j], belief.var_a[j],
               belief.cov_ab[j], belief.var_b[j]);
  }
}

void filter_joints(const JointFilterModel& model, double dt_s, std::span<const double> encoder_rad,
                   JointBelief& belief) {
  check_dt(dt_s);
  check_finite_readings(model, encoder_rad);
  ARTTRACK_CHECK_ARGUMENT(belief.size() == model.num_joints());
  const int n = model.num_joints();
  const int ne = model.num_encoder_joints();
  const double* rate_a = model.angle_rate_var().data();
  const double* rate_b = model.bias_rate_var().data();
  const double* k = model.bias_decay_rate_per_s().data();
  const double* r = model.encoder_var_rad2().data();
  double* ma = belief.mean_a.data();
  double* mb = belief.mean_b.data();
  double* paa = belief.var_a.data();
  double* pab = belief.cov_ab.data();
  double* pbb = belief.var_b.data();
  BiasTransition bias(dt_s);
  for (int j = 0; j < ne; ++j) {
    bias.set(k[j]);
    predict_one(bias, dt_s, rate_a[j], rate_b[j], mb[j], paa[j], pab[j], pbb[j]);
    update_one(encoder_rad[j], r[j], ma[j], mb[j], paa[j], pab[j], pbb[j]);
  }
  // Virtual joints: random walk only (no bias, no encoder).
  for (int j = ne; j < n; ++j) paa[j] += rate_a[j] * dt_s;
}

void fold_angle_posteriors(std::span<const double> mean_a, std::span<const double> var_a,
                           JointBelief& belief) {
  ARTTRACK_CHECK_ARGUMENT(int(mean_a.size()) == belief.size() &&
                          int(var_a.size()) == belief.size());
  for (int j = 0; j < belief.size(); ++j) {
    belief.set_joint(j, fold_angle_marginal(belief.joint(j), mean_a[j], var_a[j]));
  }
}

}  // namespace arttrack
