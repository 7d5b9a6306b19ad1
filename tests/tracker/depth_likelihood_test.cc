#include "arttrack/tracker/internal/depth_likelihood.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "../error_of.h"
#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

constexpr OccluderModel kModels[] = {OccluderModel::kTruncated, OccluderModel::kIndependent};

// The model written down literally as in docs/method.md "Depth image likelihood"
// (kTruncated) or the header (kIndependent), in linear space: the
// independent reference where its numbers are representable.
double naive_density(const DepthModelParams& p, double z, double r) {
  const double w = p.outlier_weight, Z = p.max_range_m, l = p.occluder_decay_per_m;
  const double s = p.noise_std_m + p.noise_quadratic_per_m * z * z;
  const double gauss = std::exp(-(z - r) * (z - r) / (2 * s * s)) / (std::sqrt(2 * M_PI) * s);
  const double p_vis = w / Z + (1 - w) * gauss;
  double p_occ;
  if (std::isinf(r)) {
    p_occ = w / Z + (1 - w) * l * std::exp(-l * z + l * l * s * s / 2);
  } else if (p.occluder_model == OccluderModel::kIndependent) {
    const double po = p.occlusion_prior;
    const double occluder = l * std::exp(-l * z + l * l * s * s / 2) *
                            (1 + std::erf((r - z + l * s * s) / (std::sqrt(2.0) * s))) / 2;
    return w / Z + (1 - w) * ((1 - po + po * std::exp(-l * r)) * gauss + po * occluder);
  } else {
    p_occ = w / Z + (1 - w) * l * std::exp(l * (r - z) + l * l * s * s / 2) *
                        (1 + std::erf((r - z + l * s * s) / (std::sqrt(2.0) * s))) /
                        (2 * (std::exp(l * r) - 1));
  }
  return (1 - p.occlusion_prior) * (std::isinf(r) ? w / Z : p_vis) + p.occlusion_prior * p_occ;
}

// Composite Simpson over (0, Z] of p(z|r), with a step fine enough for the
// 3 mm Gaussian peak (sigma / 40).
double integrate_density(const DepthLikelihood& lik, double r) {
  const double Z = lik.params().max_range_m;
  const double h_target = lik.params().noise_std_m / 40;
  const int n = 2 * int(std::ceil(Z / h_target / 2));
  const double h = Z / n;
  // The density is finite at z -> 0+; evaluate the left end just inside.
  double sum =
      std::exp(lik.log_likelihood_pixel(1e-12, r)) + std::exp(lik.log_likelihood_pixel(Z, r));
  for (int i = 1; i < n; ++i) {
    sum += (i % 2 ? 4 : 2) * std::exp(lik.log_likelihood_pixel(i * h, r));
  }
  return sum * h / 3;
}

TEST(DepthLikelihood, DensityIntegratesToOneOverTheSensorRange) {
  for (double po : {0.0, 0.25, 0.5, 0.9})
    for (OccluderModel model : kModels) {
      DepthModelParams p;
      p.occluder_model = model;
      p.occlusion_prior = po;
      const DepthLikelihood lik(p);
      for (double r : {0.3, 0.7, 1.5, 3.0, 5.0}) {
        EXPECT_NEAR(integrate_density(lik, r), 1.0, 1e-3) << "p_o " << po << " r " << r;
      }
    }
}

TEST(DepthLikelihood, LogSpaceEqualsNaiveEvaluation) {
  std::mt19937_64 rng(1);
  for (double s1 : {0.0, 0.002}) {
    for (double po : {0.0, 0.25, 1.0})
      for (OccluderModel model : kModels) {
        DepthModelParams p;
        p.occluder_model = model;
        p.noise_quadratic_per_m = s1;
        p.occlusion_prior = po;
        const DepthLikelihood lik(p);
        std::uniform_real_distribution<double> depth(0.05, p.max_range_m);
        int compared = 0;
        for (int i = 0; i < 20000; ++i) {
          const double z = depth(rng);
          // r near z often (where the Gaussian and erf matter), else anywhere.
          const double r = i % 2 ? z + std::normal_distribution<double>(0, 0.02)(rng) : depth(rng);
          if (r <= 0) continue;
          for (double rr : {r, kInf}) {
            const double naive = naive_density(p, z, rr);
            if (!std::isnormal(naive)) continue;
            const double ref = std::log(naive);
            EXPECT_NEAR(lik.log_likelihood_pixel(z, rr), ref, 1e-9 * std::max(1.0, std::abs(ref)))
                << "z " << z << " r " << rr;
            ++compared;
          }
        }
        EXPECT_GT(compared, 30000);
      }
  }
}

TEST(DepthLikelihood, FiniteEverywhereIncludingExtremes) {
  const double zs[] = {1e-9, 1e-6, 1e-3, 0.01, 0.5, 1.0, 3.0, 5.999, 6.0};
  const double rs[] = {1e-9, 1e-6, 1e-3, 0.01, 0.5, 1.0, 3.0, 5.999, 6.0, kInf};
  for (double sigma : {1e-6, 1e-4, 0.003, 0.1}) {
    for (double w : {1e-9, 0.01, 1.0}) {
      for (double po : {0.0, 0.25, 1.0})
        for (OccluderModel model : kModels) {
          DepthModelParams p;
          p.occluder_model = model;
          p.noise_std_m = sigma;
          p.outlier_weight = w;
          p.occlusion_prior = po;
          DepthLikelihood lik(p);
          DepthImage observed(p.width, p.height), rendered(p.width, p.height);
          int i = 0;
          for (double z : zs) {
            for (double r : rs) {
              const double ll = lik.log_likelihood_pixel(z, r);
              const double lr = lik.log_ratio_pixel(z, r);
              ASSERT_TRUE(std::isfinite(ll)) << z << " " << r << " sigma " << sigma << " w " << w;
              ASSERT_TRUE(std::isfinite(lr)) << z << " " << r << " sigma " << sigma << " w " << w;
              observed.depth_m[i] = float(z);
              rendered.depth_m[i] = float(r);
              ++i;
            }
          }
          lik.set_observation(observed);
          ASSERT_TRUE(std::isfinite(lik.log_ratio(rendered)));
        }
    }
  }
}

TEST(DepthLikelihood, UncoveredPixelsAddExactlyZero) {
  const DepthLikelihood lik0{DepthModelParams{}};
  for (double z : {1e-6, 0.4, 2.0, 6.0}) EXPECT_EQ(lik0.log_ratio_pixel(z, kInf), 0.0);

  DepthModelParams p;
  DepthLikelihood lik(p);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<float> depth(0.2f, 6.f);
  DepthImage observed(p.width, p.height);
  for (float& z : observed.depth_m) z = depth(rng);
  lik.set_observation(observed);
  DepthImage nothing(p.width, p.height, 0.f);
  EXPECT_EQ(lik.log_ratio(nothing), 0.0);
  DepthImage at_infinity(p.width, p.height, std::numeric_limits<float>::infinity());
  EXPECT_EQ(lik.log_ratio(at_infinity), 0.0);
  // A covered region: the score is the sum over it alone, whatever the
  // observed depths elsewhere.
  DepthImage rendered(p.width, p.height, 0.f);
  double expected = 0;
  for (int v = 10; v < 20; ++v) {
    for (int u = 30; u < 45; ++u) {
      rendered.at(u, v) = 1.0f;
      expected += lik.log_ratio_pixel(observed.at(u, v), 1.0f);
    }
  }
  EXPECT_NEAR(lik.log_ratio(rendered), expected, 1e-9 * std::abs(expected));
  for (int i = 0; i < p.width * p.height; ++i) {
    if (rendered.depth_m[i] == 0.f) observed.depth_m[i] = depth(rng);
  }
  lik.set_observation(observed);
  EXPECT_NEAR(lik.log_ratio(rendered), expected, 1e-9 * std::abs(expected));
}

TEST(DepthLikelihood, InvalidObservedPixelsAreSkipped) {
  DepthModelParams p;
  DepthLikelihood lik(p);
  DepthImage observed(p.width, p.height, 1.5f);
  observed.at(0, 0) = 0.f;
  observed.at(1, 0) = std::nanf("");
  observed.at(2, 0) = 7.f;  // beyond the 6 m range
  observed.at(3, 0) = -1.f;
  observed.at(4, 0) = std::numeric_limits<float>::infinity();
  lik.set_observation(observed);
  EXPECT_EQ(lik.num_valid_pixels(), p.width * p.height - 5);
  DepthImage rendered(p.width, p.height, 0.f);
  for (int u = 0; u < 5; ++u) rendered.at(u, 0) = 1.5f;
  EXPECT_EQ(lik.log_ratio(rendered), 0.0);
  rendered.at(5, 0) = 1.5f;  // one valid covered pixel
  EXPECT_NEAR(lik.log_ratio(rendered), lik.log_ratio_pixel(1.5, 1.5), 1e-12);
}

// The fast image path against the sum of the log-space reference, over
// random images with about 30% coverage, different parameter sets, and the
// rectangle version.
TEST(DepthLikelihood, ImageScoreEqualsSumOfReferencePixels) {
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 24; ++trial) {
    DepthModelParams p;
    p.occluder_model = kModels[trial / 12];
    p.noise_std_m = trial % 3 == 0 ? 0.003 : trial % 3 == 1 ? 1e-5 : 0.02;
    p.noise_quadratic_per_m = trial % 2 ? 0.0 : 0.0015;
    p.occlusion_prior = trial % 4 == 0 ? 0.0 : 0.25 * (trial % 4);
    p.outlier_weight = trial % 5 == 0 ? 1e-6 : 0.01;
    DepthLikelihood lik(p);
    std::uniform_real_distribution<float> depth(0.2f, 6.f), u01(0.f, 1.f);
    std::normal_distribution<float> near(0.f, 0.01f);
    DepthImage observed(p.width, p.height), rendered(p.width, p.height, 0.f);
    for (int i = 0; i < p.width * p.height; ++i) {
      observed.depth_m[i] = u01(rng) < 0.05f ? 0.f : depth(rng);
      const float c = u01(rng);
      if (c < 0.15f) {
        rendered.depth_m[i] = std::max(0.01f, observed.depth_m[i] + near(rng));  // on the surface
      } else if (c < 0.3f) {
        rendered.depth_m[i] = depth(rng);  // anywhere
      }
    }
    lik.set_observation(observed);
    double expected = 0, scale = 0;
    for (int i = 0; i < p.width * p.height; ++i) {
      const float z = observed.depth_m[i], r = rendered.depth_m[i];
      if (z > 0 && r > 0) {
        const double t = lik.log_ratio_pixel(z, r);
        expected += t;
        scale += std::abs(t);
      }
    }
    EXPECT_NEAR(lik.log_ratio(rendered), expected, 1e-9 * scale) << "trial " << trial;

    // Rectangle over a full-size buffer and over a compact copy.
    const PixelRect rect{7, 5, 7 + 33, 5 + 21};
    double expected_rect = 0;
    std::vector<float> compact(size_t(rect.width()) * rect.height());
    for (int v = 0; v < rect.height(); ++v) {
      for (int u = 0; u < rect.width(); ++u) {
        const float z = observed.at(rect.u0 + u, rect.v0 + v);
        const float r = rendered.at(rect.u0 + u, rect.v0 + v);
        compact[size_t(v) * rect.width() + u] = r;
        if (z > 0 && r > 0) expected_rect += lik.log_ratio_pixel(z, r);
      }
    }
    const float* start = rendered.depth_m.data() + size_t(rect.v0) * p.width + rect.u0;
    EXPECT_NEAR(lik.log_ratio(start, p.width, rect), expected_rect, 1e-9 * scale);
    EXPECT_NEAR(lik.log_ratio(compact.data(), rect.width(), rect), expected_rect, 1e-9 * scale);
  }
}

TEST(DepthLikelihood, FavoursTheObservedDepthAndToleratesOcclusion) {
  const DepthLikelihood lik{DepthModelParams{}};
  const double r = 1.2;
  // Unoccluded: the score peaks at r = z.
  double best_r = 0, best = -kInf;
  for (double rr = 1.0; rr <= 1.4; rr += 0.0005) {
    const double s = lik.log_ratio_pixel(1.2, rr);
    if (s > best) best = s, best_r = rr;
  }
  EXPECT_NEAR(best_r, 1.2, 0.001);
  EXPECT_GT(best, 2.0);  // a robot at the observed depth is well supported

  // Observed 30 cm in front of the robot (occluded): a mild penalty against
  // the peak, where a pure Gaussian of the same noise would be at -5000.
  const double peak = lik.log_likelihood_pixel(r, r);
  const double occluded = lik.log_likelihood_pixel(r - 0.3, r);
  const double gaussian_drop = -0.3 * 0.3 / (2 * 0.003 * 0.003);
  EXPECT_GT(occluded - peak, -10.0);
  EXPECT_LT(gaussian_drop, -4000.0);
  // In front (occlusion can explain it) is far likelier than behind (only
  // the outlier density can).
  EXPECT_GT(lik.log_likelihood_pixel(r - 0.3, r) - lik.log_likelihood_pixel(r + 0.3, r), 3.0);
  // And seeing the background far behind where the robot is rendered
  // counts against the hypothesis.
  EXPECT_LT(lik.log_ratio_pixel(r + 0.3, r), -1.0);
}

// A robot pixel rendered well behind the observed surface (hidden by an
// occluder): the paper's truncated occluder density pays log 1 / (1 -
// exp(-lambda r)) for it, the independent model nothing, as for a pixel the
// hypothesis does not cover. A visible match is supported by both alike.
TEST(DepthLikelihood, HidingTheRobotPaysOnlyUnderTheTruncatedModel) {
  DepthModelParams p;
  p.occluder_model = OccluderModel::kTruncated;
  const DepthLikelihood truncated(p);
  p.occluder_model = OccluderModel::kIndependent;
  const DepthLikelihood independent(p);
  const double lambda = p.occluder_decay_per_m;
  for (double r : {0.5, 1.0, 1.5, 3.0}) {
    const double z = r - 0.3;  // the occluder, 30 cm in front
    const double pays = -std::log(-std::expm1(-lambda * r));
    EXPECT_NEAR(truncated.log_ratio_pixel(z, r), pays, 0.01) << r;
    EXPECT_GT(pays, 0.05);
    EXPECT_NEAR(independent.log_ratio_pixel(z, r), 0.0, 1e-6) << r;
    EXPECT_GT(independent.log_ratio_pixel(r, r), 5.0) << r;
    EXPECT_NEAR(independent.log_ratio_pixel(r, r), truncated.log_ratio_pixel(r, r), 1.0) << r;
    EXPECT_LT(independent.log_ratio_pixel(r + 0.3, r), -1.0) << r;
  }
}

TEST(DepthLikelihood, SubsamplesLargerObservations) {
  DepthModelParams p;
  DepthLikelihood lik(p);
  DepthImage big(640, 480, 2.0f);
  lik.set_observation(big);
  EXPECT_EQ(lik.num_valid_pixels(), 80 * 60);
  DepthImage rendered(80, 60, 2.0f);
  EXPECT_NEAR(lik.log_ratio(rendered), 80 * 60 * lik.log_ratio_pixel(2.0, 2.0), 1e-7);
}

TEST(DepthLikelihood, RejectsBadParameters) {
  DepthModelParams p;
  p.outlier_weight = 0;
  EXPECT_THROW(DepthLikelihood{p}, InputError);
  p = {};
  p.noise_std_m = -0.001;
  EXPECT_THROW(DepthLikelihood{p}, InputError);
  p = {};
  p.occlusion_prior = 1.5;
  const std::string error = test_support::error_of([&] { p.validate("tracker.yaml depth"); });
  EXPECT_NE(error.find("occlusion_prior"), std::string::npos) << error;
  EXPECT_NE(error.find("tracker.yaml"), std::string::npos) << error;
}

}  // namespace
}  // namespace arttrack
