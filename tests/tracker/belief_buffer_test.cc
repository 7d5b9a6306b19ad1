#include "arttrack/tracker/internal/belief_buffer.h"

#include <gtest/gtest.h>

#include <vector>

#include "../error_of.h"
#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

TEST(BeliefBufferTest, KeepsTheNewestEntriesInOrderWhenFull) {
  BeliefBuffer buffer(1, 2, 4);
  for (int k = 0; k < 7; ++k) {
    const std::vector<double> m{double(k)}, s{10.0 * k, -1.0 * k};
    buffer.push(0.001 * k, m, s);
  }
  ASSERT_EQ(buffer.size(), 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(buffer.time(i), 0.001 * (i + 3));
    EXPECT_EQ(buffer.measurement(i)[0], i + 3);
    EXPECT_EQ(buffer.state(i)[0], 10.0 * (i + 3));
    EXPECT_EQ(buffer.state(i)[1], -1.0 * (i + 3));
  }
}

TEST(BeliefBufferTest, FindsTheLastEntryAtOrBeforeATime) {
  BeliefBuffer buffer(0, 0, 8);
  for (int k = 0; k < 12; ++k) buffer.push(1.0 + k, {}, {});  // keeps times 5..12
  EXPECT_EQ(buffer.last_at_or_before(4.99), -1);
  EXPECT_EQ(buffer.last_at_or_before(5.0), 0);
  EXPECT_EQ(buffer.last_at_or_before(7.5), 2);
  EXPECT_EQ(buffer.last_at_or_before(12.0), 7);
  EXPECT_EQ(buffer.last_at_or_before(100.0), 7);
}

TEST(BeliefBufferTest, TimeGoingBackwardsIsAnErrorNamingBothTimes) {
  BeliefBuffer buffer(0, 0, 4);
  buffer.push(2.0, {}, {});
  buffer.push(2.0, {}, {});  // equal time stamps are allowed
  const std::string error = test_support::error_of([&] { buffer.push(1.5, {}, {}); });
  EXPECT_NE(error.find("backwards"), std::string::npos) << error;
  EXPECT_NE(error.find("1.5"), std::string::npos) << error;
  EXPECT_EQ(buffer.size(), 2);
}

TEST(BeliefBufferTest, MutableStateWritesThrough) {
  BeliefBuffer buffer(0, 1, 3);
  const std::vector<double> s{1.0};
  buffer.push(0.0, {}, s);
  buffer.push(1.0, {}, s);
  buffer.mutable_state(1)[0] = 42.0;
  EXPECT_EQ(buffer.state(1)[0], 42.0);
  EXPECT_EQ(buffer.state(0)[0], 1.0);
}

}  // namespace
}  // namespace arttrack
