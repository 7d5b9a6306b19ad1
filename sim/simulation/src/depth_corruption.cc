#include "arttrack/sim/depth_corruption.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

[[noreturn]] void fail_field(const char* what, const std::string& field, double value) {
  std::ostringstream msg;
  msg << what << ": " << field << " (got " << value << ")";
  throw InputError(msg.str());
}

void require(bool ok, const char* what, const std::string& field, double value) {
  if (!ok) fail_field(what, field, value);
}

bool is_probability(double p) { return p >= 0.0 && p <= 1.0; }

}  // namespace

void DepthCorruptionParams::validate() const {
  const char* what = "depth corruption";
  require(std::abs(depth_scale_error) <= 0.2, what, "depth_scale_error must be in [-0.2, 0.2]",
          depth_scale_error);
  require(noise_sigma0_m >= 0.0 && std::isfinite(noise_sigma0_m), what,
          "noise_sigma0_m must be >= 0", noise_sigma0_m);
  require(noise_sigma_quadratic_per_m >= 0.0 && std::isfinite(noise_sigma_quadratic_per_m), what,
          "noise_sigma_quadratic_per_m must be >= 0", noise_sigma_quadratic_per_m);
  require(baseline_focal_m_px >= 0.0 && std::isfinite(baseline_focal_m_px), what,
          "baseline_focal_m_px must be >= 0", baseline_focal_m_px);
  require(disparity_step_px > 0.0 && std::isfinite(disparity_step_px), what,
          "disparity_step_px must be > 0", disparity_step_px);
  require(is_probability(dropout_probability), what, "dropout_probability must be in [0, 1]",
          dropout_probability);
  require(edge_jump_m > 0.0, what, "edge_jump_m must be > 0", edge_jump_m);
  require(is_probability(edge_dropout_probability), what,
          "edge_dropout_probability must be in [0, 1]", edge_dropout_probability);
  require(min_range_m >= 0.0 && std::isfinite(min_range_m), what, "min_range_m must be >= 0",
          min_range_m);
  require(max_range_m > min_range_m, what, "max_range_m must be > min_range_m", max_range_m);
}

DepthCorruption::DepthCorruption(const DepthCorruptionParams& params, std::uint64_t seed)
    : params_(params), rng_(seed) {
  params_.validate();
}

bool DepthCorruption::on_edge(const DepthImage& image, int u, int v) const {
  // No return is infinitely far, so any neighbour without one makes an edge.
  constexpr float kFar = std::numeric_limits<float>::infinity();
  auto depth = [&](int x, int y) {
    const float z = image.at(x, y);
    return z > 0.f && std::isfinite(z) ? z : kFar;
  };
  float lo = depth(u, v), hi = lo;
  auto take = [&](int x, int y) {
    const float z = depth(x, y);
    lo = std::min(lo, z), hi = std::max(hi, z);
  };
  if (u > 0) take(u - 1, v);
  if (u + 1 < image.width) take(u + 1, v);
  if (v > 0) take(u, v - 1);
  if (v + 1 < image.height) take(u, v + 1);
  return double(hi) - double(lo) > params_.edge_jump_m;
}

void DepthCorruption::corrupt(const DepthImage& exact, DepthImage& out) {
  if (&exact == &out) throw std::invalid_argument("DepthCorruption::corrupt: out is the input");
  const DepthCorruptionParams& p = params_;
  out.width = exact.width;
  out.height = exact.height;
  out.depth_m.resize(exact.depth_m.size());
  const bool noisy = p.noise_sigma0_m > 0.0 || p.noise_sigma_quadratic_per_m > 0.0;
  for (int v = 0; v < exact.height; ++v) {
    for (int u = 0; u < exact.width; ++u) {
      const double z = exact.at(u, v);
      float& result = out.at(u, v);
      result = 0.f;
      if (!(z > 0.0) || !std::isfinite(z)) continue;
      if (p.edge_dropout_probability > 0.0 && on_edge(exact, u, v) &&
          uniform_(rng_) < p.edge_dropout_probability)
        continue;
      if (p.dropout_probability > 0.0 && uniform_(rng_) < p.dropout_probability) continue;
      double measured = z * (1.0 + p.depth_scale_error);
      if (noisy) measured += p.noise_sigma_m(z) * normal_(rng_);
      if (p.baseline_focal_m_px > 0.0 && measured > 0.0) {
        // Round the disparity, not the depth: steps grow with z^2.
        const double steps = std::round(p.baseline_focal_m_px / (measured * p.disparity_step_px));
        measured = steps > 0.0 ? p.baseline_focal_m_px / (steps * p.disparity_step_px) : 0.0;
      }
      if (!(measured > 0.0) || measured > p.max_range_m || measured < p.min_range_m) continue;
      result = float(measured);
    }
  }
}

void CameraTiming::validate() const {
  const char* what = "camera timing";
  require(rate_hz > 0.0 && std::isfinite(rate_hz), what, "rate_hz must be > 0", rate_hz);
  require(first_frame_s >= 0.0 && std::isfinite(first_frame_s), what, "first_frame_s must be >= 0",
          first_frame_s);
  require(latency_s >= 0.0 && std::isfinite(latency_s), what, "latency_s must be >= 0", latency_s);
  require(jitter_s >= 0.0 && std::isfinite(jitter_s), what, "jitter_s must be >= 0", jitter_s);
  require(drop_probability >= 0.0 && drop_probability < 1.0, what,
          "drop_probability must be in [0, 1)", drop_probability);
}

std::vector<CameraFrame> camera_frames(const CameraTiming& timing, double duration_s,
                                       std::uint64_t seed) {
  timing.validate();
  require(duration_s >= 0.0 && std::isfinite(duration_s), "camera timing",
          "duration_s must be >= 0", duration_s);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto draw_delay = [&] {
    if (timing.jitter_s == 0.0) return timing.latency_s;
    for (;;) {  // truncated to >= 0 by redrawing (accepts at least half)
      const double spread =
          timing.jitter == CameraTiming::Jitter::kGaussian ? normal(rng) : 2.0 * uniform(rng) - 1.0;
      const double delay = timing.latency_s + timing.jitter_s * spread;
      if (delay >= 0.0) return delay;
    }
  };
  std::vector<CameraFrame> frames;
  double last_arrival_s = -std::numeric_limits<double>::infinity();
  for (int k = 0;; ++k) {
    // From the index, not by accumulation, so stamps do not drift.
    const double stamp = timing.first_frame_s + k / timing.rate_hz;
    if (stamp > duration_s) break;
    CameraFrame f;
    f.index = k;
    f.stamp_s = stamp;
    // Always both draws, so one frame's drop does not shift later delays.
    f.arrival_s = std::max(stamp + draw_delay(), last_arrival_s);
    f.dropped = uniform(rng) < timing.drop_probability;
    if (!f.dropped) last_arrival_s = f.arrival_s;
    frames.push_back(f);
  }
  return frames;
}

}  // namespace arttrack::sim
