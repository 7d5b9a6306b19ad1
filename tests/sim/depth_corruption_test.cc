#include "arttrack/sim/depth_corruption.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "../expect_error.h"
#include "arttrack/tracker/error.h"

namespace arttrack::sim {
namespace {

using test_support::expect_error_naming;

// Mean and standard deviation of the returns of an image (0 skipped).
struct Moments {
  double mean = 0, sd = 0;
  int n = 0;
};
Moments moments(const DepthImage& image) {
  double s = 0, s2 = 0;
  int n = 0;
  for (float z : image.depth_m)
    if (z > 0.f) s += z, s2 += double(z) * z, ++n;
  const double mean = s / n;
  return {mean, std::sqrt(s2 / n - mean * mean), n};
}

TEST(DepthCorruption, DefaultsChangeNothing) {
  DepthImage exact(8, 6, 1.5f);
  exact.at(2, 3) = 0.f;
  exact.at(5, 1) = 4.25f;
  DepthImage out;
  DepthCorruption(DepthCorruptionParams{}, 1).corrupt(exact, out);
  EXPECT_EQ(out.width, 8);
  EXPECT_EQ(out.height, 6);
  EXPECT_EQ(out.depth_m, exact.depth_m);
}

TEST(DepthCorruption, NoiseStdGrowsAsS0PlusS1ZSquared) {
  DepthCorruptionParams p;
  p.noise_sigma0_m = 0.002;
  p.noise_sigma_quadratic_per_m = 0.003;
  DepthCorruption corruption(p, 17);
  for (double z : {1.0, 3.0}) {
    const DepthImage exact(300, 200, float(z));
    DepthImage out;
    corruption.corrupt(exact, out);
    const Moments m = moments(out);
    const double sigma = 0.002 + 0.003 * z * z;  // 5 mm at 1 m, 29 mm at 3 m
    ASSERT_EQ(m.n, 300 * 200);
    // Five standard errors of the mean and of the standard deviation.
    EXPECT_NEAR(m.mean, z, 5 * sigma / std::sqrt(m.n)) << z;
    EXPECT_NEAR(m.sd, sigma, 5 * sigma / std::sqrt(2.0 * m.n)) << z;
  }
}

TEST(DepthCorruption, DisparityQuantisationStepsGrowWithDepthSquared) {
  DepthCorruptionParams p;
  p.baseline_focal_m_px = 43.5;
  p.disparity_step_px = 0.125;
  DepthCorruption corruption(p, 1);
  for (double z0 : {1.0, 3.0}) {
    // A ramp of depths across one row: the outputs take discrete levels.
    DepthImage exact(2000, 1);
    for (int u = 0; u < 2000; ++u) exact.at(u, 0) = float(z0 + 1e-5 * u);
    DepthImage out;
    corruption.corrupt(exact, out);
    std::set<float> levels;
    for (int u = 0; u < 2000; ++u) {
      const double z = exact.at(u, 0), q = out.at(u, 0);
      // A level is 43.5 / (k / 8) for an integer k, the nearest in disparity.
      const double k = 43.5 / (q * 0.125);
      EXPECT_NEAR(k, std::round(k), 1e-3 * k);
      EXPECT_LE(std::abs(43.5 / q - 43.5 / z), 0.0625 * (1 + 1e-5));
      levels.insert(out.at(u, 0));
    }
    // Spacing of consecutive levels: 0.125 z^2 / 43.5 (2.9 mm at 1 m, 26 mm
    // at 3 m).
    const double step = 0.125 * z0 * z0 / 43.5;
    if (z0 == 1.0) {
      ASSERT_GE(levels.size(), 4u);
      auto it = levels.begin();
      const double first = *it++;
      EXPECT_NEAR(*it - first, step, 0.03 * step);
    } else {
      ASSERT_LE(levels.size(), 2u);  // a 2 cm ramp is within one 26 mm step
    }
  }
}

TEST(DepthCorruption, RandomDropoutRate) {
  DepthCorruptionParams p;
  p.dropout_probability = 0.2;
  DepthCorruption corruption(p, 3);
  const DepthImage exact(250, 200, 2.0f);
  DepthImage out;
  corruption.corrupt(exact, out);
  const int n = 250 * 200;
  int zeros = 0;
  for (std::size_t i = 0; i < out.depth_m.size(); ++i) {
    if (out.depth_m[i] == 0.f) {
      ++zeros;
    } else {
      EXPECT_EQ(out.depth_m[i], 2.0f);  // survivors untouched
    }
  }
  EXPECT_NEAR(double(zeros) / n, 0.2, 5 * std::sqrt(0.2 * 0.8 / n));
}

TEST(DepthCorruption, EdgeDropoutOnlyAtDepthEdges) {
  // Left half 1 m, right half 2 m, a smooth slope in the bottom rows (0.5 mm
  // per pixel, no edge), and a hole with no return in the middle.
  const int W = 100, H = 80;
  DepthImage exact(W, H);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u)
      exact.at(u, v) = v >= 60 ? float(1.0 + 0.0005 * u) : u < 50 ? 1.f : 2.f;
  for (int v = 20; v < 30; ++v)
    for (int u = 20; u < 30; ++u) exact.at(u, v) = 0.f;
  auto is_edge = [&](int u, int v) {
    if (v < 60 && (u == 49 || u == 50)) return true;   // the step
    if ((v == 59 || v == 60) && u >= 50) return true;  // 2 m above the slope
    // The 4-neighbours of the hole.
    const bool ring = u >= 19 && u <= 30 && v >= 19 && v <= 30 &&
                      !(u >= 20 && u < 30 && v >= 20 && v < 30) &&
                      !((u == 19 || u == 30) && (v == 19 || v == 30));
    return ring;
  };
  DepthCorruptionParams p;
  p.edge_jump_m = 0.05;
  p.edge_dropout_probability = 1.0;
  DepthImage out;
  DepthCorruption(p, 5).corrupt(exact, out);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u)
      EXPECT_EQ(out.at(u, v), is_edge(u, v) ? 0.f : exact.at(u, v)) << u << "," << v;

  p.edge_dropout_probability = 0.5;
  DepthCorruption(p, 5).corrupt(exact, out);
  int edges = 0, dropped = 0;
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      if (is_edge(u, v)) {
        ++edges;
        dropped += out.at(u, v) == 0.f;
      } else {
        EXPECT_EQ(out.at(u, v), exact.at(u, v));
      }
    }
  EXPECT_NEAR(double(dropped) / edges, 0.5, 5 * std::sqrt(0.25 / edges));
}

TEST(DepthCorruption, RangeLimits) {
  DepthCorruptionParams p;
  p.min_range_m = 0.5;
  p.max_range_m = 6.0;
  DepthImage exact(4, 1);
  exact.at(0, 0) = 0.3f;
  exact.at(1, 0) = 0.7f;
  exact.at(2, 0) = 5.9f;
  exact.at(3, 0) = 6.1f;
  DepthImage out;
  DepthCorruption(p, 1).corrupt(exact, out);
  EXPECT_EQ(out.depth_m, (std::vector<float>{0.f, 0.7f, 5.9f, 0.f}));
}

// A calibration error of the depth scales every return alike, before the
// range limits; pixels without return stay without.
TEST(DepthCorruption, DepthScaleErrorScalesEveryReturn) {
  DepthCorruptionParams p;
  p.depth_scale_error = -0.01;
  p.max_range_m = 4.0;
  DepthImage exact(4, 1);
  exact.at(0, 0) = 0.f;
  exact.at(1, 0) = 1.0f;
  exact.at(2, 0) = 2.5f;
  exact.at(3, 0) = 4.02f;  // 3.9798 m measured: within range
  DepthImage out;
  DepthCorruption(p, 1).corrupt(exact, out);
  EXPECT_EQ(out.depth_m[0], 0.f);
  EXPECT_FLOAT_EQ(out.depth_m[1], 0.99f);
  EXPECT_FLOAT_EQ(out.depth_m[2], 2.475f);
  EXPECT_FLOAT_EQ(out.depth_m[3], float(4.02f * 0.99));
}

TEST(DepthCorruption, SameSeedSameImages) {
  DepthCorruptionParams p;
  p.noise_sigma0_m = 0.001;
  p.noise_sigma_quadratic_per_m = 0.002;
  p.dropout_probability = 0.1;
  p.edge_dropout_probability = 0.5;
  p.baseline_focal_m_px = 43.5;
  DepthImage exact(64, 48, 1.2f);
  for (int v = 0; v < 48; ++v)
    for (int u = 30; u < 64; ++u) exact.at(u, v) = 2.5f;
  auto run = [&](std::uint64_t seed) {
    DepthCorruption c(p, seed);
    DepthImage a, b;
    c.corrupt(exact, a);
    c.corrupt(exact, b);  // a second image continues the stream
    EXPECT_NE(a.depth_m, b.depth_m);
    a.depth_m.insert(a.depth_m.end(), b.depth_m.begin(), b.depth_m.end());
    return a.depth_m;
  };
  EXPECT_EQ(run(99), run(99));
  EXPECT_NE(run(99), run(100));
}

TEST(CameraFrames, StampsAtTheRateDelaysNeverNegativeAndInOrder) {
  for (CameraTiming::Jitter jitter :
       {CameraTiming::Jitter::kGaussian, CameraTiming::Jitter::kUniform}) {
    CameraTiming t;
    t.rate_hz = 30.0;
    t.latency_s = 0.01;
    t.jitter_s = 0.02;  // often "negative" before truncation
    t.jitter = jitter;
    const std::vector<CameraFrame> frames = camera_frames(t, 100.0, 4);
    ASSERT_EQ(frames.size(), 3001u);  // 0, 1/30, ..., 100 s
    double last_arrival = 0.0;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      const CameraFrame& f = frames[k];
      EXPECT_EQ(f.index, int(k));
      EXPECT_NEAR(f.stamp_s, k / 30.0, 1e-12);
      EXPECT_GE(f.arrival_s, f.stamp_s);
      if (jitter == CameraTiming::Jitter::kUniform) {
        EXPECT_LE(f.arrival_s - f.stamp_s, 0.03 + 1e-12);
      }
      if (!f.dropped) {
        EXPECT_GE(f.arrival_s, last_arrival);
        last_arrival = f.arrival_s;
      }
    }
  }
}

TEST(CameraFrames, MeanLatencyAndDropRate) {
  CameraTiming t;
  t.rate_hz = 30.0;
  t.first_frame_s = 0.5;
  t.latency_s = 0.05;
  t.jitter_s = 0.004;  // far from 0 and from overtaking: no truncation
  t.drop_probability = 0.1;
  const std::vector<CameraFrame> frames = camera_frames(t, 600.0, 12);
  ASSERT_EQ(frames.size(), std::size_t(599.5 * 30) + 1);
  EXPECT_EQ(frames.front().stamp_s, 0.5);
  double sum = 0, sum2 = 0;
  int dropped = 0;
  for (const CameraFrame& f : frames) {
    const double d = f.arrival_s - f.stamp_s;
    sum += d, sum2 += d * d;
    dropped += f.dropped;
  }
  const double n = frames.size(), mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.05, 5 * 0.004 / std::sqrt(n));
  EXPECT_NEAR(sd, 0.004, 5 * 0.004 / std::sqrt(2 * n));
  EXPECT_NEAR(dropped / n, 0.1, 5 * std::sqrt(0.09 / n));
}

TEST(CameraFrames, DeterministicFromSeed) {
  CameraTiming t;
  t.latency_s = 0.03;
  t.jitter_s = 0.01;
  t.drop_probability = 0.2;
  auto flat = [&](std::uint64_t seed) {
    std::vector<double> v;
    for (const CameraFrame& f : camera_frames(t, 10.0, seed))
      v.insert(v.end(), {f.stamp_s, f.arrival_s, double(f.dropped)});
    return v;
  };
  EXPECT_EQ(flat(5), flat(5));
  EXPECT_NE(flat(5), flat(6));
}

TEST(DepthCorruption, BadInputIsNamed) {
  DepthCorruptionParams p;
  p.dropout_probability = 1.5;
  expect_error_naming([&] { DepthCorruption(p, 1); }, "dropout_probability");
  p = {};
  p.max_range_m = 0.0;
  expect_error_naming([&] { DepthCorruption(p, 1); }, "max_range_m");
  p = {};
  p.noise_sigma_quadratic_per_m = -0.1;
  expect_error_naming([&] { DepthCorruption(p, 1); }, "noise_sigma_quadratic_per_m");
  p = {};
  p.depth_scale_error = 0.3;
  expect_error_naming([&] { DepthCorruption(p, 1); }, "depth_scale_error");
  p.depth_scale_error = std::nan("");
  expect_error_naming([&] { DepthCorruption(p, 1); }, "depth_scale_error");
  CameraTiming t;
  t.rate_hz = 0.0;
  expect_error_naming([&] { camera_frames(t, 1.0, 1); }, "rate_hz");
  t = {};
  t.latency_s = -0.01;
  expect_error_naming([&] { camera_frames(t, 1.0, 1); }, "latency_s");
  t = {};
  expect_error_naming([&] { camera_frames(t, -1.0, 1); }, "duration_s");
}

}  // namespace
}  // namespace arttrack::sim
