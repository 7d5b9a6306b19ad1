// TrackerStats keeps fixed-size timings: the most recent
// ImageTimings::kCapacity images and the count and means of all, so a
// tracker's memory does not grow with run time.
#include <gtest/gtest.h>

#include <vector>

#include "arttrack/tracker/tracker.h"

namespace arttrack {
namespace {

ImageTiming timing(int k) { return {0.033 * k, 10.0 + k, 1.0 + k, 0.5 * k, 20.0 + k}; }

TEST(ImageTimings, KeepsEveryImageBelowTheBoundInOrder) {
  ImageTimings t;
  EXPECT_TRUE(t.empty());
  EXPECT_EQ(t.mean_update_ms(), 0);
  for (int k = 0; k < 5; ++k) t.add(timing(k));
  ASSERT_EQ(t.size(), 5u);
  EXPECT_EQ(t.total(), 5);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(t[k].stamp_s, timing(k).stamp_s);
    EXPECT_EQ(t[k].latency_ms, timing(k).latency_ms);
  }
  EXPECT_EQ(t.values(&ImageTiming::update_ms), (std::vector<double>{10, 11, 12, 13, 14}));
  EXPECT_DOUBLE_EQ(t.mean_refilter_ms(), 3);
}

TEST(ImageTimings, BoundedAfterTheBoundOldestDropped) {
  ImageTimings t;
  const int n = int(ImageTimings::kCapacity) * 3 + 7;
  for (int k = 0; k < n; ++k) t.add(timing(k));
  ASSERT_EQ(t.size(), ImageTimings::kCapacity);
  EXPECT_EQ(t.total(), n);
  // The most recent kCapacity images, oldest first.
  const int first = n - int(ImageTimings::kCapacity);
  for (std::size_t k = 0; k < t.size(); ++k)
    ASSERT_EQ(t[k].update_ms, timing(first + int(k)).update_ms);
  // Means over every image ever added: 10 + (n - 1) / 2.
  EXPECT_DOUBLE_EQ(t.mean_update_ms(), 10.0 + (n - 1) / 2.0);
  // Stats of a tracker carry nothing else that grows.
  TrackerStats stats;
  for (int k = 0; k < n; ++k) stats.images.add(timing(k));
  EXPECT_EQ(stats.images.size(), ImageTimings::kCapacity);
}

}  // namespace
}  // namespace arttrack
