// A bounded, time-ordered record of joint measurements and of the belief
// after each one, so that a delayed depth image can be applied at its own
// time stamp and the later measurements re-filtered
// (docs/method.md "Delayed images"; paper Sec. IV-C).
//
// The buffer is agnostic of what a belief is: it stores each as a flat
// vector of `state_size` doubles (the filter bank saves and loads its state
// that way). Storage is a ring allocated once; pushing never allocates.
#pragma once

#include <span>
#include <vector>

namespace arttrack {

class BeliefBuffer {
 public:
  // `capacity` entries of `measurement_size` readings and `state_size` belief
  // values each.
  BeliefBuffer(int measurement_size, int state_size, int capacity);

  // Appends a measurement taken at `time_s` and the belief after it. Time must
  // not go backwards (InputError naming both times); equal times are allowed.
  // When full, the oldest entry is overwritten.
  void push(double time_s, std::span<const double> measurement, std::span<const double> state);

  int size() const { return size_; }
  int capacity() const { return capacity_; }
  bool empty() const { return size_ == 0; }
  void clear() { size_ = 0; }

  // Entries by age: 0 is the oldest, size() - 1 the newest.
  double time(int i) const { return times_[slot(i)]; }
  std::span<const double> measurement(int i) const;
  std::span<const double> state(int i) const;
  // The belief after entry i, for re-filtering in place.
  std::span<double> mutable_state(int i);

  double oldest_time() const { return time(0); }
  double newest_time() const { return time(size_ - 1); }

  // The newest entry with time <= t_s, or -1 when t_s is older than every
  // entry (the buffer no longer reaches back that far).
  int last_at_or_before(double t_s) const;

 private:
  int slot(int i) const { return (head_ + i) % capacity_; }

  int measurement_size_;
  int state_size_;
  int capacity_;
  int head_ = 0;  // slot of the oldest entry
  int size_ = 0;
  std::vector<double> times_;
  std::vector<double> measurements_;
  std::vector<double> states_;
};

}  // namespace arttrack
