// Depth image likelihood of rendered robot hypotheses (paper Eqs. (1)-(2),
// the pixel model of Wüthrich et al., IROS 2013;
// docs/method.md "Depth image likelihood").
//
// Per pixel, with observed depth z and the hypothesis' rendered depth r
// (r = infinity where the ray misses the robot), noise sigma = s0 + s1 z^2,
// outlier weight w, maximum range Z, occluder decay lambda, occlusion prior p_o:
//   p_vis(z|r) = w/Z + (1-w) N(z; r, sigma^2)
//   p_occ(z|r) = w/Z + (1-w) lambda exp(lambda (r-z) + lambda^2 sigma^2 / 2)
//                  (1 + erf((r - z + lambda sigma^2) / (sqrt(2) sigma))) / (2 (exp(lambda r) - 1))
//   p_occ(z|inf) = w/Z + (1-w) lambda exp(-lambda z + lambda^2 sigma^2 / 2)
//   p(z|r) = (1 - p_o) p_vis(z|r) + p_o p_occ(z|r).
// p_occ is the truncated exponential occluder density on (0, r) blurred by the
// noise, without the erf term of its lower end at depth 0 (as the original
// implementation; docs/method.md "Depth image likelihood"). A hypothesis
// scores
//   sum over valid pixels of log p(z|r) - log p(z|inf),
// so pixels it does not cover add exactly 0 and only covered pixels cost work.
//
// That is OccluderModel::kTruncated, the paper's. Its occluder density is
// renormalised on (0, r), so an observed surface in front of a rendered
// robot pixel is 1 / (1 - exp(-lambda r)) times likelier than with no robot
// there: every robot pixel hidden behind an occluder earns log of that (0.4
// to 1.2 nats at 1.5 to 0.5 m), and under a heavy occlusion hypotheses that
// tuck the arm behind the occluder win. OccluderModel::kIndependent (the
// default) is the generative model where the occluder's depth, drawn with
// probability p_o from lambda exp(-lambda d), does not depend on the robot:
// the robot is seen when there is no occluder or it lies behind the robot,
//   p(z|r) = w/Z + (1-w) [ (1 - p_o (1 - exp(-lambda r))) N(z; r, sigma^2)
//            + p_o lambda exp(-lambda z + lambda^2 sigma^2 / 2)
//              (1 + erf((r - z + lambda sigma^2) / (sqrt(2) sigma))) / 2 ],
// with the same p(z|inf). A robot pixel hidden well behind the observed
// surface then scores 0, as a pixel the hypothesis does not cover: hiding
// the arm neither pays nor costs, only what is seen counts.
//
// Depths are metres along the optical axis. An observed pixel is valid when
// it is finite and in (0, Z]; others (0 = no return, NaN, beyond range) are
// skipped. A rendered pixel covers the robot when it is finite and > 0.
// Rendered depths below 1 micrometre are taken as 1 micrometre (the model
// diverges like 1/r as r -> 0; no camera sees that close).
#pragma once

#include <cmath>
#include <cstddef>
#include <string_view>
#include <vector>

#include "arttrack/tracker/camera.h"
#include "arttrack/tracker/depth_model_params.h"

namespace arttrack {

// The likelihood of one observed image. set_observation() once per image;
// the scoring functions are const, allocation-free and safe to call from
// several threads at once.
class DepthLikelihood {
 public:
  // Throws InputError for invalid parameters.
  explicit DepthLikelihood(const DepthModelParams& params);

  const DepthModelParams& params() const { return params_; }
  int width() const { return params_.width; }
  int height() const { return params_.height; }

  // Prepares per-pixel constants for an observed image; an image of another
  // size is subsampled to width() x height() first (subsample_depth).
  void set_observation(const DepthImage& observed);

  // Score of a rendered hypothesis of size width() x height() (0 = robot not
  // there): sum of log p(z|r) - log p(z|inf) over covered valid pixels.
  double log_ratio(const DepthImage& rendered) const;

  // The same over a rectangle only (pixels outside it count as uncovered).
  // `rendered_m` points at the rendered depth of pixel (rect.u0, rect.v0);
  // consecutive rows are `row_stride` floats apart (width() for a full-size
  // buffer, rect.width for a compact one).
  double log_ratio(const float* rendered_m, std::ptrdiff_t row_stride, const PixelRect& rect) const;

  // Fast path of the hot loops: ratios[k] = p(z|r) / p(z|inf) at observed
  // pixel pixels[k] (row-major index) for rendered depth rendered_m[k] > 0,
  // rounded to float, for k < n. fast_exp/fast_erfc (fast_math.h) instead of
  // libm: within 3e-7 relative of the exact ratio (see the tests), so each
  // pixel's log is within 3e-7 of log_ratio_pixel(). An invalid observed
  // pixel gives exactly 1. Thread-safe, allocation-free.
  void ratios(const int* pixels, const float* rendered_m, int n, float* ratios) const;

  // Reference evaluation of one pixel, entirely in log space (log-sum-exp of
  // the three mixture components, asymptotic log erfc in the far tails):
  // finite for every z in (0, Z] and r in (0, Z] or +infinity.
  double log_likelihood_pixel(double z_m, double r_m) const;  // log p(z|r)
  double log_ratio_pixel(double z_m, double r_m) const;       // log p(z|r) - log p(z|inf)

  // Number of valid pixels in the current observation.
  int num_valid_pixels() const { return num_valid_; }

  // Observed depth of pixel `index` (row-major, width() x height()) of the
  // current observation, metres; 0 where the pixel is invalid.
  double observed_depth_m(int index) const {
    return pixels_[std::size_t(index)].inv_p_inf > 0 ? pixels_[std::size_t(index)].z : 0.0;
  }
  // The depth noise sigma at depth z_m, metres.
  double noise_std_at_m(double z_m) const { return sigma_m(z_m); }

 private:
  // Per observed pixel, computed once per image, so that a covered pixel
  // costs at most two exps, one erfc and a few multiplications (log_ratio()).
  struct PixelTerms {
    double z = 0;          // observed depth, m
    double inv_s = 0;      // 1 / (sqrt(2) sigma)
    double shift = 0;      // lambda sigma / sqrt(2)
    double k_vis = 0;      // (1-w)(1-p_o) / (sqrt(2 pi) sigma)
    double k_occ = 0;      // (1-w) p_o lambda exp(-lambda z + lambda^2 sigma^2 / 2) / 2
    double inv_p_inf = 0;  // 1 / p(z|inf); 0 marks an invalid pixel
    double e2_max = 0;     // ((r - z) / (sqrt(2) sigma))^2 beyond which the Gaussian is negligible
  };

  double sigma_m(double z_m) const {
    return params_.noise_std_m + params_.noise_quadratic_per_m * z_m * z_m;
  }

  DepthModelParams params_;
  double outlier_density_ = 0;  // w / Z
  std::vector<PixelTerms> pixels_;
  int num_valid_ = 0;
};

}  // namespace arttrack
