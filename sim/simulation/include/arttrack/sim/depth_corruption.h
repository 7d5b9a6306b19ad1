// What a real depth camera delivers: the rendered (exact) depth image made
// noisy, quantised and incomplete, and delivered late, irregularly and not
// always.
//
// Per pixel with a return (depth z > 0, metres along the optical axis), in
// this order:
//   0. depth scale: z becomes (1 + depth_scale_error) z, a calibration error
//      of the camera's depth (a structured-light camera's baseline or
//      reference plane; every pixel alike, a few millimetres per metre);
//   1. edge dropout: if the pixel is on a depth edge of the exact image (the
//      depths of the pixel and its 4-neighbours span more than edge_jump_m; a
//      neighbour without return counts as infinitely far), it becomes 0 with
//      probability edge_dropout_probability (structured-light cameras lose
//      silhouettes);
//   2. random dropout with probability dropout_probability;
//   3. Gaussian noise with sigma = s0 + s1 z^2 (z the exact depth)
//      (docs/method.md "Depth image likelihood");
//   4. disparity quantisation, like a Kinect: the disparity
//      d = baseline_focal / z (pixels) is rounded to a multiple of
//      disparity_step_px, so the depth step grows as
//      disparity_step_px z^2 / baseline_focal (about 3 mm at 1 m, 26 mm at
//      3 m for a Kinect v1);
//   5. range: a result beyond max_range_m or below min_range_m becomes 0.
// Pixels without return stay 0. Every component is off at its default.
#pragma once

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "arttrack/tracker/camera.h"

namespace arttrack::sim {

// Per-pixel corruption of a depth image.
struct DepthCorruptionParams {
  // Relative error of every depth, in [-0.2, 0.2] (0.005: 5 mm at 1 m).
  double depth_scale_error = 0.0;
  // Noise standard deviation at zero depth s0, m (>= 0).
  double noise_sigma0_m = 0.0;
  // Quadratic growth of the noise s1, 1/m (>= 0): sigma = s0 + s1 z^2.
  double noise_sigma_quadratic_per_m = 0.0;
  // Baseline times focal length of the disparity camera, m px (>= 0; 0: not
  // quantised). Kinect v1: 0.075 m x 580 px = 43.5.
  double baseline_focal_m_px = 0.0;
  // Disparity resolution, px (> 0). Kinect v1: 1/8.
  double disparity_step_px = 0.125;
  // Probability that any pixel loses its return, in [0, 1].
  double dropout_probability = 0.0;
  // Depth jump within a 4-neighbourhood that makes a pixel an edge, m (> 0).
  double edge_jump_m = 0.05;
  // Probability that an edge pixel loses its return, in [0, 1].
  double edge_dropout_probability = 0.0;
  // Farthest depth measured, m (> min_range_m); beyond it there is no return.
  double max_range_m = std::numeric_limits<double>::infinity();
  // Nearest depth measured, m (>= 0); nearer there is no return.
  double min_range_m = 0.0;

  // Noise standard deviation at depth z_m, m.
  double noise_sigma_m(double z_m) const {
    return noise_sigma0_m + noise_sigma_quadratic_per_m * z_m * z_m;
  }
  void validate() const;
};

// Applies DepthCorruptionParams to images with its own seeded generator:
// the same seed and the same sequence of images give the same outputs. Not
// thread-safe (one instance per simulated camera).
class DepthCorruption {
 public:
  // Throws InputError if params are invalid.
  DepthCorruption(const DepthCorruptionParams& params, std::uint64_t seed);

  // Writes the corrupted `exact` into `out` (resized; no allocation once it
  // has the size). `out` must not be `exact`: edges are found on the exact
  // image.
  void corrupt(const DepthImage& exact, DepthImage& out);

  const DepthCorruptionParams& params() const { return params_; }

 private:
  bool on_edge(const DepthImage& image, int u, int v) const;

  DepthCorruptionParams params_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  std::normal_distribution<double> normal_{0.0, 1.0};
};

// When the camera captures and when its images arrive.
struct CameraTiming {
  enum class Jitter { kGaussian, kUniform };

  // Frame rate, Hz (> 0).
  double rate_hz = 30.0;
  // Capture time of the first frame, s (>= 0).
  double first_frame_s = 0.0;
  // Mean delay from capture (the image's time stamp) to arrival, s (>= 0).
  double latency_s = 0.0;
  // Spread of the delay, s (>= 0): standard deviation (kGaussian) or
  // half-width (kUniform). Draws with a negative delay are redrawn, so the
  // delay is never negative.
  double jitter_s = 0.0;
  // Distribution of the delay around latency_s.
  Jitter jitter = Jitter::kGaussian;
  // Probability that a frame never arrives, in [0, 1).
  double drop_probability = 0.0;

  void validate() const;
};

// One captured frame.
struct CameraFrame {
  int index = 0;         // capture count from 0
  double stamp_s = 0.0;  // capture time = the image's time stamp
  // Arrival time (>= stamp_s), s. A driver delivers frames in order, so a
  // frame never arrives before an earlier delivered one. Set for dropped
  // frames too (when it would have arrived).
  double arrival_s = 0.0;
  bool dropped = false;  // never delivered
};

// Frames captured at first_frame_s + k / rate_hz for every k with a capture
// time <= duration_s, in capture order, with delays and drops drawn from a
// generator seeded with `seed`. Throws InputError for invalid timing or a
// negative duration.
std::vector<CameraFrame> camera_frames(const CameraTiming& timing, double duration_s,
                                       std::uint64_t seed);

}  // namespace arttrack::sim
