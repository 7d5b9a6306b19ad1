#include "arttrack/tracker/internal/worker_pool.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "arttrack/tracker/error.h"

namespace arttrack {

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

void WorkerPool::worker_loop(int worker) {
  std::uint64_t seen = 0;
  for (;;) {
    int n;
    Call call;
    void* context;
    {
      std::unique_lock lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      n = job_n_;
      call = job_call_;
      context = job_context_;
    }
    const int begin = int(std::int64_t(n) * worker / num_workers_);
    const int end = int(std::int64_t(n) * (worker + 1) / num_workers_);
    std::exception_ptr error;
    if (begin < end) {
      try {
        call(context, begin, end, worker);
      } catch (...) {
        error = std::current_exception();
      }
    }
    std::lock_guard lock(mutex_);
    if (error && !error_) error_ = error;
    if (--remaining_ == 0) done_.notify_one();
  }
}

void WorkerPool::run(int n, Call call, void* context) {
  if (n <= 0) return;
  if (num_workers_ == 1) {
    call(context, 0, n, 0);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    job_n_ = n;
    job_call_ = call;
    job_context_ = context;
    error_ = nullptr;
    remaining_ = num_workers_ - 1;
    ++generation_;
  }
  start_.notify_all();
  std::exception_ptr error;
  const int end = int(std::int64_t(n) / num_workers_);
  if (end > 0) {
    try {
      call(context, 0, end, 0);
    } catch (...) {
      error = std::current_exception();
    }
  }
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return remaining_ == 0; });
  if (!error) error = error_;
  error_ = nullptr;
  if (error) std::rethrow_exception(error);
}

}  // namespace arttrack
