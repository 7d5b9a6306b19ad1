// The joints' noise, as configured: per physical joint the encoder noise,
// the angle's and the bias's diffusion and the bias's decay (paper Eqs.
// (3)-(5)); per virtual (camera offset) joint a random walk. The filters
// that use them are internal (joint_filter.h).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "arttrack/tracker/units.h"

namespace arttrack {

// Noise parameters of one physical (encoder) joint. Continuous time. The
// fields say rad; a prismatic joint's hold metres (its encoder reads a
// position, its bias is an offset): TrackerConfig::prismatic_joint_defaults.
struct JointFilterParams {
  // The defaults are tracker/config/default.yaml's, in its degrees
  // (DefaultConfigTest checks them field by field).
  // Encoder noise standard deviation sigma_q, rad (paper Eq. (3)).
  double encoder_noise_rad = 0.057 * kRadPerDeg;
  // Angle random-walk diffusion sigma_a, rad/sqrt(s): the angle's standard
  // deviation grows by sigma_a sqrt(dt) over dt (Eq. (4)). Large enough to
  // follow fast motion between encoder readings.
  double angle_diffusion_rad_per_sqrt_s = 57.3 * kRadPerDeg;
  // Bias diffusion sigma_b, rad/sqrt(s) (Eq. (5) in continuous time): how
  // far a bias can wander in a second that no image confirms. 1.6 degrees,
  // half the 3.2 it was: under a partial occlusion or at the image's edge
  // the wrist's few visible pixels let a faster bias drift 5-16 degrees
  // within seconds (docs/accuracy.md, "The bias process"); the bias ramps of
  // time_varying_bias.yaml (5 degrees per second) and of the paper files (10
  // degrees in 1 s) are still followed, the latter a few millimetres later.
  double bias_diffusion_rad_per_sqrt_s = 1.6 * kRadPerDeg;
  // Bias decay c per second, 0 < c < 1: over dt the bias mean is multiplied
  // by c^dt. With sigma_b above, the stationary bias std is 9.9 degrees (the
  // prior of the first image) and its time constant 1 / ln(1/c) = 76 s.
  double bias_decay_per_s = 0.987;
  // False: this joint's bias is not estimated (fixed at 0, variance 0); the
  // filter is then a 1-D filter on the angle. The original implementation's
  // "bias factor 0".
  bool estimate_bias = true;

  // Stationary bias standard deviation sigma_b / sqrt(2 ln(1/c)), rad (0 when
  // the bias is not estimated).
  double stationary_bias_std_rad() const;

  // Throws ConfigKeyError (error.h) naming `source` and the key, `prefix`
  // followed by the field's YAML name in degrees (e.g.
  // "joints.per_joint.elbow.encoder_noise_deg"), for a value outside its
  // range: encoder noise in (0, 90] degrees, angle diffusion in [0, 1e5]
  // deg/sqrt(s), bias diffusion in (0, 1e5] deg/sqrt(s) ([0, 1e5] when the
  // bias is not estimated), c in (0, 1). `linear`: a prismatic joint's, in
  // metres (encoder_noise_m in (0, 1], position_diffusion_m_per_sqrt_s in
  // [0, 1e3], bias_diffusion_m_per_sqrt_s in (0, 1e3]).
  void validate(std::string_view source, const std::string& prefix = "", bool linear = false) const;
};

// The configuration keys of a joint's three noises, in the units of its
// kind: a revolute or continuous joint's in degrees, a prismatic joint's in
// metres. The one table the configuration is read, checked and explained by.
struct JointNoiseKeys {
  const char* encoder_noise;     // JointFilterParams::encoder_noise_rad
  const char* motion_diffusion;  // angle_diffusion_rad_per_sqrt_s
  const char* bias_diffusion;    // bias_diffusion_rad_per_sqrt_s
  double unit;                   // a key's value times unit: the field's (rad or m)
  // Largest encoder noise and diffusion, in the key's unit.
  double max_encoder_noise, max_diffusion;
};
inline constexpr JointNoiseKeys kRevoluteNoiseKeys{"encoder_noise_deg",
                                                   "angle_diffusion_deg_per_sqrt_s",
                                                   "bias_diffusion_deg_per_sqrt_s",
                                                   kRadPerDeg,
                                                   90,
                                                   1e5};
inline constexpr JointNoiseKeys kPrismaticNoiseKeys{"encoder_noise_m",
                                                    "position_diffusion_m_per_sqrt_s",
                                                    "bias_diffusion_m_per_sqrt_s",
                                                    1.0,
                                                    1,
                                                    1e3};
inline const JointNoiseKeys& joint_noise_keys(bool linear) {
  return linear ? kPrismaticNoiseKeys : kRevoluteNoiseKeys;
}

// Some of one joint's parameters, over the defaults for its kind of joint
// (TrackerConfig::joint_overrides, a YAML joints.per_joint entry). The
// numbers are radians, or metres when `linear` (the entry gave _m keys: a
// prismatic joint's); `linear` is unset when only unit-free keys were given
// (bias_decay_per_s, estimate_bias), which suit either kind.
struct JointFilterOverride {
  std::optional<double> encoder_noise;
  std::optional<double> motion_diffusion_per_sqrt_s;  // angle or position
  std::optional<double> bias_diffusion_per_sqrt_s;
  std::optional<double> bias_decay_per_s;
  std::optional<bool> estimate_bias;
  std::optional<bool> linear;

  // Every field of `p`, for a revolute or continuous joint.
  static JointFilterOverride all_of(const JointFilterParams& p);
  // `defaults` with the fields given here.
  JointFilterParams over(JointFilterParams defaults) const;
};

// Noise of one virtual (camera offset) joint: a random walk around the
// nominal camera pose, no encoder, no bias. Metres for the three prismatic
// joints, radians for the three revolute ones.
struct VirtualJointParams {
  // Random-walk diffusion, m/sqrt(s) or rad/sqrt(s).
  double diffusion_per_sqrt_s = 0.005;
  // Standard deviation of the initial belief around 0, m or rad: how far the
  // true camera may be from the kinematic model's camera.
  double initial_std = 0.03;
  // Random-walk diffusion per square root of the radians (or metres) the
  // joints that carry the camera travel, m/sqrt(rad) or rad/sqrt(rad): a
  // camera on a pan-tilt head whose axes and origins are a little off its
  // URDF sees its offset change as the head turns, not as time passes
  // (camera_carrier_motion.h).
  double motion_diffusion_per_sqrt_rad = 0;
};

}  // namespace arttrack
