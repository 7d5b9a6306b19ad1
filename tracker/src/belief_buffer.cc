#include "arttrack/tracker/internal/belief_buffer.h"

#include <algorithm>
#include <sstream>

#include "arttrack/tracker/error.h"

namespace arttrack {

BeliefBuffer::BeliefBuffer(int measurement_size, int state_size, int capacity)
    : measurement_size_(measurement_size),
      state_size_(state_size),
      capacity_(capacity),
      times_(capacity),
      measurements_(size_t(capacity) * measurement_size),
      states_(size_t(capacity) * state_size) {
  ARTTRACK_CHECK_ARGUMENT(capacity > 0 && measurement_size >= 0 && state_size >= 0);
}

void BeliefBuffer::push(double time_s, std::span<const double> measurement,
                        std::span<const double> state) {
  ARTTRACK_CHECK_ARGUMENT(int(measurement.size()) == measurement_size_ &&
                          int(state.size()) == state_size_);
  if (size_ > 0 && time_s < newest_time()) {
    std::ostringstream os;
    os.precision(9);
    os << "joint measurement time stamp goes backwards: " << time_s << " s after " << newest_time()
       << " s";
    throw InputError(os.str());
  }
  int s;
  if (size_ < capacity_) {
    s = slot(size_);
    ++size_;
  } else {
    s = head_;  // overwrite the oldest
    head_ = (head_ + 1) % capacity_;
  }
  times_[s] = time_s;
  std::copy(measurement.begin(), measurement.end(),
            measurements_.begin() + size_t(s) * measurement_size_);
  std::copy(state.begin(), state.end(), states_.begin() + size_t(s) * state_size_);
}

std::span<const double> BeliefBuffer::measurement(int i) const {
  return {measurements_.data() + size_t(slot(i)) * measurement_size_, size_t(measurement_size_)};
}

std::span<const double> BeliefBuffer::state(int i) const {
  return {states_.data() + size_t(slot(i)) * state_size_, size_t(state_size_)};
}

std::span<double> BeliefBuffer::mutable_state(int i) {
  return {states_.data() + size_t(slot(i)) * state_size_, size_t(state_size_)};
}

int BeliefBuffer::last_at_or_before(double t_s) const {
  if (size_ == 0 || t_s < oldest_time()) return -1;
  // Binary search over the ring in age order: times are non-decreasing.
  int lo = 0, hi = size_ - 1;
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (time(mid) <= t_s)
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

}  // namespace arttrack
