// The fast exp and erfc of the likelihood's hot loop, and the fast pixel
// ratios built on them, against libm and the exact log-space reference.
#include "arttrack/tracker/internal/fast_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "arttrack/tracker/internal/depth_likelihood.h"

#pragma GCC diagnostic ignored "-Wpsabi"  // Double4 values in a test, no ABI crossing

namespace arttrack {
namespace {

TEST(FastMath, ExpMatchesLibmToWellBelowTheLikelihoodTolerance) {
  double worst = 0;
  for (double x = -708; x <= 709; x += 0.0137) {
    const double exact = std::exp(x);
    worst = std::max(worst, std::abs(fast_exp(x) / exact - 1));
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(fast_exp(0.0), 1.0);
  EXPECT_EQ(fast_exp(-709.0), 0.0);
  EXPECT_EQ(fast_exp(-1e6), 0.0);
  EXPECT_TRUE(std::isnan(fast_exp(std::numeric_limits<double>::quiet_NaN())));
}

// The Numerical Recipes fit claims a fractional error below 1.2e-7 for z >= 0;
// for y < 0, 2 - erfc(|y|) is at least 1, so the error only shrinks.
TEST(FastMath, ErfcHasTheDocumentedRelativeError) {
  double worst = 0;
  for (double y = -8; y <= 26.5; y += 0.00173) {
    const double exact = std::erfc(y);
    if (exact < 1e-300) continue;
    worst = std::max(worst, std::abs(fast_erfc(y) / exact - 1));
  }
  EXPECT_LT(worst, 1.2e-7);
  EXPECT_GT(worst, 1e-9);  // it is an approximation: the bound above is what protects us
  EXPECT_EQ(fast_erfc(40.0), 0.0);
  EXPECT_NEAR(fast_erfc(-40.0), 2.0, 1e-15);
}

// The lane-wise versions compute the same operations: the same bits.
TEST(FastMath, LaneWiseVersionsGiveTheScalarBits) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> any(-750, 30);
  for (int i = 0; i < 20000; ++i) {
    const Double4 x = {any(rng), any(rng) / 20, -any(rng) / 100, any(rng) / 700};
    const Double4 e = fast_exp(x), c = fast_erfc(x);
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(e[k], fast_exp(x[k])) << x[k];
      EXPECT_EQ(c[k], fast_erfc(x[k])) << x[k];
    }
    const Double8 x8 = {x[0], x[1], x[2], x[3], -x[0], -x[1] / 3, x[2] * 7, any(rng)};
    const Double8 e8 = fast_exp(x8), c8 = fast_erfc(x8);
    for (int k = 0; k < 8; ++k) {
      EXPECT_EQ(e8[k], fast_exp(x8[k])) << x8[k];
      EXPECT_EQ(c8[k], fast_erfc(x8[k])) << x8[k];
    }
  }
}

// DepthLikelihood::ratios() against exp(log_ratio_pixel()) wherever that is
// a normal double: the error budget is fast_erfc's 1.2e-7 (the occluded
// term is at most the whole density), fast_exp's 1e-12, and float rounding
// of the result (6e-8): 3e-7 in all.
TEST(FastMath, PixelRatiosMatchTheExactLikelihood) {
  std::mt19937_64 rng(7);
  double worst = 0;
  for (double s1 : {0.0, 0.002}) {
    for (double po : {0.0, 0.25, 1.0}) {
      for (double lambda : {0.001, 0.693, 50.0}) {
        for (OccluderModel model : {OccluderModel::kTruncated, OccluderModel::kIndependent}) {
          DepthModelParams p;
          p.occluder_model = model;
          p.width = 64;
          p.height = 64;
          p.noise_quadratic_per_m = s1;
          p.occlusion_prior = po;
          p.occluder_decay_per_m = lambda;
          if (lambda * (p.noise_std_m + s1 * 36) > 1) p.max_range_m = 2;
          DepthLikelihood lik(p);
          std::uniform_real_distribution<double> depth(0.02, p.max_range_m);
          DepthImage observed(p.width, p.height);
          for (float& z : observed.depth_m) z = float(depth(rng));
          observed.depth_m[5] = 0;  // no return: ratio exactly 1
          lik.set_observation(observed);
          std::vector<int> pixel;
          std::vector<float> rendered;
          for (int i = 0; i < p.width * p.height; ++i) {
            const double z = observed.depth_m[i];
            // Near the observation (the Gaussian and erfc matter), in front
            // (occlusion), far behind, and tiny depths.
            const double pick[] = {z + std::normal_distribution<double>(0, 0.01)(rng), z - 0.3,
                                   z + 1.0, 1e-7, depth(rng)};
            const double r = pick[i % 5];
            if (r <= 0) continue;
            pixel.push_back(i);
            rendered.push_back(float(r));
          }
          std::vector<float> ratio(pixel.size());
          lik.ratios(pixel.data(), rendered.data(), int(pixel.size()), ratio.data());
          for (size_t k = 0; k < pixel.size(); ++k) {
            const double z = observed.depth_m[pixel[k]];
            if (z == 0) {
              EXPECT_EQ(ratio[k], 1.f);
              continue;
            }
            const double exact = std::exp(lik.log_ratio_pixel(z, rendered[k]));
            if (!std::isnormal(exact)) continue;
            const double err = std::abs(ratio[k] / exact - 1);
            worst = std::max(worst, err);
            EXPECT_LT(err, 3e-7) << "z " << z << " r " << rendered[k] << " p_o " << po << " lambda "
                                 << lambda << " s1 " << s1 << " model " << int(model);
          }
        }
      }
    }
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
}

}  // namespace
}  // namespace arttrack
