#include "arttrack/tracker/internal/depth_likelihood.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "arttrack/tracker/error.h"
#include "arttrack/tracker/internal/fast_math.h"
#include "config_range.h"

namespace arttrack {
namespace {

constexpr double kSqrt2 = 1.41421356237309505;
constexpr double kLogSqrt2Pi = 0.91893853320467274;  // log sqrt(2 pi)
constexpr double kLogSqrtPi = 0.57236494292470008;   // log sqrt(pi)
constexpr double kLog2 = 0.69314718055994531;
constexpr double kNegInf = -std::numeric_limits<double>::infinity();
constexpr double kMinRenderedDepthM = 1e-6;
constexpr double kErfc6_5 = 3.85e-20;  // >= erfc(6.5) = 3.8421e-20

// log(erfc(y)) for any finite y. std::erfc is accurate (relative) while its
// result is a normal double, i.e. up to y ~ 26.5; from y = 25 on the
// asymptotic expansion
//   erfc(y) = exp(-y^2) / (y sqrt(pi)) (1 + sum_k (-1)^k (2k-1)!! / (2y^2)^k)
// is used in log form; its 7th term is below 3e-17 there.
double log_erfc(double y) {
  if (y < 25) return std::log(std::erfc(y));
  const double t = 1 / (2 * y * y);
  double term = 1, sum = 0;
  for (int k = 1; k <= 7; ++k) {
    term *= -(2 * k - 1) * t;
    sum += term;
  }
  return -y * y - std::log(y) - kLogSqrtPi + std::log1p(sum);
}

// log(exp(a) + exp(b) + exp(c)), any of them may be -inf (not all three).
double log_sum_exp(double a, double b, double c) {
  const double m = std::max({a, b, c});
  return m + std::log(std::exp(a - m) + std::exp(b - m) + std::exp(c - m));
}

// log x, or -inf for x == 0 (a mixture weight of zero).
double log_weight(double x) { return x > 0 ? std::log(x) : kNegInf; }

}  // namespace

void DepthModelParams::validate(std::string_view source, const std::string& prefix) const {
  check_range(source, prefix + "outlier_weight", outlier_weight, ConfigRange::closed(1e-9, 1));
  check_range(source, prefix + "noise_std_m", noise_std_m, ConfigRange::closed(1e-6, 0.5));
  check_range(source, prefix + "noise_quadratic_per_m", noise_quadratic_per_m,
              ConfigRange::closed(0, 1));
  check_range(source, prefix + "max_range_m", max_range_m, ConfigRange::closed(0.1, 100));
  check_range(source, prefix + "occluder_decay_per_m", occluder_decay_per_m,
              ConfigRange::closed(1e-3, 100));
  check_range(source, prefix + "occlusion_prior", occlusion_prior, ConfigRange::closed(0, 1));
  check_range(source, prefix + "width", width, ConfigRange::closed(4, 4096));
  check_range(source, prefix + "height", height, ConfigRange::closed(3, 4096));
  // The noise at the maximum range must stay small against the occluder
  // decay length (lambda sigma <= 1): it bounds the per-pixel ratios that
  // log_ratio() multiplies (see there), and a noise of a decay length would
  // make the occluder model meaningless anyway.
  const double sigma_max = noise_std_m + noise_quadratic_per_m * max_range_m * max_range_m;
  if (occluder_decay_per_m * sigma_max > 1)
    fail_key(source, prefix + "occluder_decay_per_m",
             "= " + std::to_string(occluder_decay_per_m) + " times the depth noise at " + prefix +
                 "max_range_m (" + std::to_string(sigma_max) + " m) is " +
                 std::to_string(occluder_decay_per_m * sigma_max) + ": it must be at most 1");
}

DepthLikelihood::DepthLikelihood(const DepthModelParams& params) : params_(params) {
  params_.validate("depth likelihood");
  outlier_density_ = params_.outlier_weight / params_.max_range_m;
  pixels_.resize(size_t(params_.width) * params_.height);
}

double DepthLikelihood::log_likelihood_pixel(double z_m, double r_m) const {
  const double w = params_.outlier_weight;
  const double po = params_.occlusion_prior;
  const double lambda = params_.occluder_decay_per_m;
  const double sigma = sigma_m(z_m);
  const double log_out = std::log(outlier_density_);
  // Occluded, common part: log((1-w) p_o lambda) - lambda z + lambda^2 sigma^2 / 2.
  const double log_occ_base = log_weight((1 - w) * po) + std::log(lambda) - lambda * z_m +
                              0.5 * lambda * lambda * sigma * sigma;
  if (std::isinf(r_m)) return log_sum_exp(log_out, kNegInf, log_occ_base);
  const double r = std::max(r_m, kMinRenderedDepthM);
  const double d = (z_m - r) / sigma;
  const double log_vis =
      log_weight((1 - w) * (1 - po)) - 0.5 * d * d - std::log(sigma) - kLogSqrt2Pi;
  // exp(lambda (r - z)) / (exp(lambda r) - 1) = exp(-lambda z) / (1 - exp(-lambda r)),
  // with expm1 for small lambda r; (1 + erf(x)) / 2 = erfc(-x) / 2.
  const double x = (r - z_m + lambda * sigma * sigma) / (kSqrt2 * sigma);
  const double log_occ = log_occ_base + log_erfc(-x) - kLog2;
  if (params_.occluder_model == OccluderModel::kTruncated) {
    return log_sum_exp(log_out, log_vis, log_occ - std::log(-std::expm1(-lambda * r)));
  }
  // Seen unless an occluder lies in front: 1 - p_o + p_o exp(-lambda r).
  const double log_seen = log_weight((1 - w) * (1 - po * -std::expm1(-lambda * r))) - 0.5 * d * d -
                          std::log(sigma) - kLogSqrt2Pi;
  return log_sum_exp(log_out, log_seen, log_occ);
}

double DepthLikelihood::log_ratio_pixel(double z_m, double r_m) const {
  if (std::isinf(r_m)) return 0;
  return log_likelihood_pixel(z_m, r_m) -
         log_likelihood_pixel(z_m, std::numeric_limits<double>::infinity());
}

void DepthLikelihood::set_observation(const DepthImage& observed) {
  const DepthImage* image = &observed;
  DepthImage resized;
  if (observed.width != params_.width || observed.height != params_.height) {
    resized = subsample_depth(observed, params_.width, params_.height);
    image = &resized;
  }
  const double w = params_.outlier_weight;
  const double po = params_.occlusion_prior;
  const double lambda = params_.occluder_decay_per_m;
  // kIndependent scales the Gaussian per rendered depth (log_ratio()).
  const double seen = params_.occluder_model == OccluderModel::kTruncated ? 1 - po : 1;
  const double k_vis = (1 - w) * seen / std::sqrt(2 * M_PI);
  const double k_occ = (1 - w) * po * lambda * 0.5;
  num_valid_ = 0;
  for (size_t i = 0; i < pixels_.size(); ++i) {
    const double z = image->depth_m[i];
    PixelTerms& t = pixels_[i];
    if (!(z > 0 && z <= params_.max_range_m)) {  // also rejects NaN
      t = PixelTerms{};
      continue;
    }
    const double sigma = sigma_m(z);
    t.z = z;
    t.inv_s = 1 / (kSqrt2 * sigma);
    t.shift = lambda * sigma / kSqrt2;
    t.k_vis = k_vis / sigma;
    t.k_occ = k_occ * std::exp(-lambda * z + 0.5 * lambda * lambda * sigma * sigma);
    // p(z|inf) = w/Z + (1-w) p_o lambda exp(-lambda z + lambda^2 sigma^2 / 2) >= w/Z > 0.
    t.inv_p_inf = 1 / (outlier_density_ + 2 * t.k_occ);
    // k_vis exp(-e^2) < 2^-60 w/Z  <=>  e^2 > log(k_vis Z / w) + 60 log 2.
    t.e2_max = t.k_vis > 0 ? std::log(t.k_vis / outlier_density_) + 60 * kLog2 : -1;
    ++num_valid_;
  }
}

double DepthLikelihood::log_ratio(const DepthImage& rendered) const {
  ARTTRACK_CHECK_ARGUMENT(rendered.width == params_.width && rendered.height == params_.height);
  return log_ratio(rendered.depth_m.data(), rendered.width,
                   PixelRect{0, 0, rendered.width, rendered.height});
}

// The hot loop. Each covered pixel multiplies p(z|r) / p(z|inf) into a
// running product instead of adding its logarithm: every density is at least
// w/Z > 0 (a floor that cannot underflow), and with the validated parameters
// (w/Z >= 1e-12, sigma >= 1e-6, lambda in [1e-3, 100], lambda sigma <= 1,
// r >= 1e-6) one ratio lies within about 1e-15..1e18, so eight of them cannot
// leave the double range; every eight pixels the product is renormalised by frexp into
// mantissa and binary exponent. One log per image instead of one per pixel,
// and no cancellation: the result equals the sum of log_ratio_pixel() to
// rounding (checked by the tests).
double DepthLikelihood::log_ratio(const float* rendered_m, std::ptrdiff_t row_stride,
                                  const PixelRect& rect) const {
  ARTTRACK_CHECK_ARGUMENT(rect.u0 >= 0 && rect.v0 >= 0 && rect.u1 <= params_.width &&
                          rect.v1 <= params_.height);
  const double lambda = params_.occluder_decay_per_m;
  const double floor = outlier_density_;
  const bool truncated = params_.occluder_model == OccluderModel::kTruncated;
  const double po = params_.occlusion_prior;
  double product = 1;
  long exponent = 0;
  int pending = 0;
  for (int v = 0; v < rect.height(); ++v) {
    const float* row = rendered_m + v * row_stride;
    const PixelTerms* terms = pixels_.data() + size_t(rect.v0 + v) * params_.width + rect.u0;
    for (int u = 0; u < rect.width(); ++u) {
      const float rf = row[u];
      // Uncovered (0), and also NaN or +inf: add exactly 0.
      if (!(rf > 0.f) || rf == std::numeric_limits<float>::infinity()) continue;
      const PixelTerms& t = terms[u];
      if (t.inv_p_inf == 0) continue;  // invalid observed pixel
      const double r = std::max(double(rf), kMinRenderedDepthM);
      const double e = (r - t.z) * t.inv_s;
      // 1 - exp(-lambda r); exp is as accurate as expm1 once it is >= 0.39.
      const double lr = lambda * r;
      const double one_minus = lr >= 0.5 ? 1 - std::exp(-lr) : -std::expm1(-lr);
      double p = floor;
      // Beyond e2_max the Gaussian is under half an ulp of p: skipping its
      // exp changes nothing (and avoids libm's slow underflow path).
      // (kIndependent's factor 1 - p_o (1 - exp(-lambda r)) <= 1 keeps that so.)
      if (e * e < t.e2_max) {
        const double gauss = t.k_vis * std::exp(-e * e);
        p += truncated ? gauss : gauss * (1 - po * one_minus);
      }
      // Occluded part: k_occ erfc(-x), over 1 - exp(-lambda r) when truncated.
      // erfc(-x) is 2 to double precision for x > 6 and below 1e-320 for x < -27.
      const double x = e + t.shift;
      if (x > -27) {
        const double scale = truncated ? t.k_occ / one_minus : t.k_occ;
        if (x > 6) {
          p += 2 * scale;
        } else if (x > -6.5 || scale * kErfc6_5 > 0x1p-60 * p) {
          // Below x = -6.5 (observed well behind the robot) the term is at
          // most scale erfc(6.5); when that is under half an ulp of p, adding
          // it would not change p, so erfc is skipped without any effect.
          p += scale * std::erfc(-x);
        }
      }
      product *= p * t.inv_p_inf;
      if (++pending == 8) {
        int e2;
        product = std::frexp(product, &e2);
        exponent += e2;
        pending = 0;
      }
    }
  }
  return std::log(product) + double(exponent) * kLog2;
}

// The same pixel model as log_ratio(), without its branches: every term is
// computed (fast_exp and fast_erfc return 0 far in the tails, where the
// exact loop skips the term), eight pixels at a time (fast_math.h's Double8)
// on structure-of-arrays chunks gathered first. 1 - exp(-lambda r) takes its
// Taylor series below lambda r = 0.01, where the subtraction would cancel.
// The AVX-512 and AVX2 clones run the same operations (no FMA), so every
// clone gives the same bits.
// The vector helpers are inlined (and the clones' resolver passes no
// vectors): GCC's ABI note about vector arguments does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"
namespace {

constexpr int kChunk = 64;  // a multiple of the lanes

struct RatioChunk {
  alignas(64) double r[kChunk], z[kChunk], inv_s[kChunk], shift[kChunk], k_vis[kChunk],
      k_occ[kChunk], inv_p_inf[kChunk], ratio[kChunk];
};

#if defined(__clang__)
// Clang rejects (not only warns about) wider vectors passed through even
// always-inlined calls in code compiled without AVX: its builds (fuzzing,
// tools/fuzz.sh) take two SSE2 lanes, the same arithmetic on every pixel.
using V = Double2;
constexpr int kLanes = 2;
#define ARTTRACK_CHUNK_CLONES
#else
using V = Double8;
constexpr int kLanes = 8;
#define ARTTRACK_CHUNK_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#endif

[[gnu::always_inline]] inline V load(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// Ratios of the first n (a multiple of kLanes) pixels of the chunk. Eight
// lanes: one AVX-512 register, or two independent AVX2 / four SSE2 chains
// that hide each other's latency.
// truncated_flag is 1 for kTruncated, 0 for kIndependent, seen_po is p_o for
// kIndependent and 0 for kTruncated: the factors they select multiply or
// divide by exactly 1 where they do not apply.
ARTTRACK_CHUNK_CLONES void chunk_ratios(RatioChunk& c, int n, double lambda, double floor,
                                        double truncated_flag, double seen_po) {
  for (int k = 0; k < n; k += kLanes) {
    const V r = load(c.r + k);
    const V e = (r - load(c.z + k)) * load(c.inv_s + k);
    const V gauss = load(c.k_vis + k) * fast_exp(-e * e);
    const V lr = lambda * r;
    const V series = lr * (1.0 - lr * (0.5 - lr * (1.0 / 6 - lr * (1.0 / 24))));
    const V one_minus = lr < 0.01 ? series : 1.0 - fast_exp(-lr);
    const V occ_divisor = one_minus * truncated_flag + (1.0 - truncated_flag);
    const V occ = load(c.k_occ + k) / occ_divisor * fast_erfc(-(e + load(c.shift + k)));
    const V seen = 1.0 - seen_po * one_minus;
    const V inv_p_inf = load(c.inv_p_inf + k);
    const V ratio = (floor + gauss * seen + occ) * inv_p_inf;
    const V result = inv_p_inf == 0.0 ? broadcast<V>(1.0) : ratio;
    std::memcpy(c.ratio + k, &result, sizeof result);
  }
}

}  // namespace

void DepthLikelihood::ratios(const int* pixels, const float* rendered_m, int n,
                             float* ratios) const {
  const double lambda = params_.occluder_decay_per_m;
  const bool truncated = params_.occluder_model == OccluderModel::kTruncated;
  RatioChunk c;
  for (int begin = 0; begin < n; begin += kChunk) {
    const int m = std::min(kChunk, n - begin);
    for (int k = 0; k < m; ++k) {
      const PixelTerms& t = pixels_[size_t(pixels[begin + k])];
      c.r[k] = std::max(double(rendered_m[begin + k]), kMinRenderedDepthM);
      c.z[k] = t.z;
      c.inv_s[k] = t.inv_s;
      c.shift[k] = t.shift;
      c.k_vis[k] = t.k_vis;
      c.k_occ[k] = t.k_occ;
      c.inv_p_inf[k] = t.inv_p_inf;
    }
    const int padded = (m + kLanes - 1) / kLanes * kLanes;
    for (int k = m; k < padded; ++k) {  // padding lanes: an invalid pixel (ratio 1)
      c.r[k] = c.z[k] = 1;
      c.inv_s[k] = c.shift[k] = c.k_vis[k] = c.k_occ[k] = c.inv_p_inf[k] = 0;
    }
    chunk_ratios(c, padded, lambda, outlier_density_, truncated ? 1.0 : 0.0,
                 truncated ? 0.0 : params_.occlusion_prior);
    for (int k = 0; k < m; ++k) ratios[begin + k] = float(c.ratio[k]);
  }
}

}  // namespace arttrack
