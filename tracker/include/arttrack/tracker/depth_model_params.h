// The depth image's pixel model, as configured: how occluders relate to the
// robot, the outlier floor, the depth noise, the sensor's range and the
// resolution the likelihood is evaluated at. The model itself, and the
// equations these parameters enter, are internal (depth_likelihood.h).
#pragma once

#include <string>
#include <string_view>

namespace arttrack {

// How the occluder's depth relates to the robot's (depth_likelihood.h).
enum class OccluderModel {
  kTruncated,    // the paper's: occluder density renormalised on (0, r)
  kIndependent,  // occluder depth independent of the robot
};

// Parameters of the pixel model (reference values of the original
// implementation as defaults).
struct DepthModelParams {
  OccluderModel occluder_model = OccluderModel::kIndependent;
  // Weight w of the uniform outlier density w / Z over the sensor range; in
  // [1e-9, 1]. Its floor under every pixel density keeps scores finite.
  double outlier_weight = 0.01;
  // Depth noise sigma = noise_std_m + noise_quadratic_per_m * z^2, metres;
  // noise_std_m in [1e-6, 0.5] (the tracker's coarsest search noise is at
  // most 0.5 and at least this), noise_quadratic_per_m in [0, 1] per metre.
  double noise_std_m = 0.003;
  double noise_quadratic_per_m = 0;
  // Sensor maximum range Z, metres, in [0.1, 100].
  double max_range_m = 6;
  // Decay rate lambda of the occluder density with distance from the camera,
  // per metre, in [1e-3, 100] (ln 2: an occluder is half as likely one metre
  // further). lambda times the noise at the maximum range must be <= 1.
  double occluder_decay_per_m = 0.69314718055994531;
  // Prior probability p_o that an external object occludes a pixel.
  double occlusion_prior = 0.25;
  // Resolution the likelihood is evaluated at (the tracker renders at it;
  // observed images are subsampled to it), width in [4, 4096], height in
  // [3, 4096].
  int width = 80;
  int height = 60;

  // Throws ConfigKeyError (error.h) naming `source` and the key, `prefix`
  // followed by the field's YAML name (e.g. "depth_model.max_range_m"), for
  // a value outside its range. The tracker's configuration checks these
  // fields here (TrackerConfig::validate), and so does DepthLikelihood.
  void validate(std::string_view source, const std::string& prefix = "") const;
};

}  // namespace arttrack
