#include "arttrack/tracker/internal/worker_pool.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "arttrack/tracker/error.h"

namespace arttrack {
namespace {

// How long a worker that has finished a job, and the caller waiting for the
// workers, watch for the next step before they sleep on the condition
// variable. The particle filter starts its next block a few microseconds
// after the last one ends (20-40 loops per image); waking a sleeping thread
// takes tens of microseconds on a virtual machine, every time.
constexpr std::chrono::microseconds kSpin{50};

// Calls done() until it is true or kSpin has passed.
template <class Done>
void spin_until(Done done) {
  const auto deadline = std::chrono::steady_clock::now() + kSpin;
  for (int k = 0;; ++k) {
    if (done()) return;
    if ((k & 63) == 63 && std::chrono::steady_clock::now() > deadline) return;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }
}

}  // namespace

WorkerPool::WorkerPool(int num_workers) {
  if (num_workers > kMaxWorkerThreads) {
    throw InputError("worker threads: " + std::to_string(num_workers) + " is more than the " +
                     std::to_string(kMaxWorkerThreads) + " allowed");
  }
  if (num_workers <= 0) {
    num_workers =
        int(std::clamp(std::thread::hardware_concurrency(), 1u, unsigned(kMaxWorkerThreads)));
  }
  num_workers_ = num_workers;
  threads_.reserve(num_workers_ - 1);
  for (int w = 1; w < num_workers_; ++w) {
    try {
      threads_.emplace_back([this, w] { worker_loop(w); });
    } catch (const std::exception& e) {
      // Workers already started wait on start_: stop them before the
      // members they use are destroyed.
      stop_and_join();
      throw std::runtime_error("cannot start worker thread " + std::to_string(w + 1) + " of " +
                               std::to_string(num_workers_) + " (" + e.what() +
                               "): ask for fewer threads");
    }
  }
}

WorkerPool::~WorkerPool() { stop_and_join(); }

void WorkerPool::stop_and_join() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (std::thread& t : threads_) t.join();
  threads_.clear();
}

std::exception_ptr WorkerPool::take_chunks(int worker) {
  const int n = job_n_, grain = job_grain_;
  for (;;) {
    const int begin = next_.fetch_add(grain, std::memory_order_relaxed);
    if (begin >= n) return nullptr;
    try {
      job_call_(job_context_, begin, std::min(n, begin + grain), worker);
    } catch (...) {
      next_.store(n, std::memory_order_relaxed);  // the others start no further chunk
      return std::current_exception();
    }
  }
}

void WorkerPool::worker_loop(int worker) {
  std::uint64_t seen = 0;
  for (;;) {
    spin_until([&] { return generation_.load(std::memory_order_acquire) != seen; });
    {
      std::unique_lock lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_.load() != seen; });
      if (stop_) return;
      seen = generation_.load();
    }
    // The job's fields were written under the mutex before generation_ moved.
    const std::exception_ptr error = take_chunks(worker);
    std::lock_guard lock(mutex_);
    if (error && !error_) error_ = error;
    if (--remaining_ == 0) done_.notify_one();
  }
}

void WorkerPool::run(int n, int grain, Call call, void* context) {
  if (n <= 0) return;
  if (num_workers_ == 1) {
    call(context, 0, n, 0);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    job_n_ = n;
    job_grain_ = std::max(1, grain);
    next_.store(0, std::memory_order_relaxed);
    job_call_ = call;
    job_context_ = context;
    error_ = nullptr;
    remaining_ = num_workers_ - 1;
    ++generation_;
  }
  start_.notify_all();
  std::exception_ptr error = take_chunks(0);
  spin_until([&] { return remaining_.load(std::memory_order_acquire) == 0; });
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return remaining_.load() == 0; });
  if (!error) error = error_;
  error_ = nullptr;
  if (error) std::rethrow_exception(error);
}

}  // namespace arttrack
