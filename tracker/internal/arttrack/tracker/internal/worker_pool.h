// Worker threads kept alive between calls, to split a loop over particles
// across cores (the particle filter's evaluations, the hypothesis
// evaluator's renders). Kept out of the filter's and the configuration's
// headers so that they need no <thread> or <mutex>.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace arttrack {

// Upper bound on a WorkerPool's workers (particle_filter.threads, arttrack
// bench --threads): more than any machine this runs on has cores, few enough
// that every worker's workspace fits in memory.
inline constexpr int kMaxWorkerThreads = 256;

// Worker threads kept alive between calls, to split particles across cores.
// One parallel_for at a time (not re-entrant); the calling thread works too.
class WorkerPool {
 public:
  // num_workers <= 0: one per hardware thread (at most kMaxWorkerThreads).
  // 1: everything in the caller. Throws InputError above kMaxWorkerThreads,
  // std::runtime_error when the system cannot start that many threads (the
  // ones already started are stopped and joined first).
  explicit WorkerPool(int num_workers = 0);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int num_workers() const { return num_workers_; }

  // Calls fn(begin, end, worker) for chunks of [0, n) that cover each index
  // once, and returns when all are done. worker in [0, W) names the thread
  // that runs the chunk (the caller is worker 0), so fn may use a workspace
  // per worker; which chunks a worker gets is not fixed: each takes the next
  // `grain` indices when it is free, so that a thread the system delays (or
  // a dearer particle) does not hold the others up at the end of the loop.
  // fn must therefore give the same result for an index on any worker. An
  // exception thrown by fn is rethrown here (no further chunk is started).
  // Does not allocate.
  template <class F>
  void parallel_for(int n, F&& fn, int grain = 1) {
    using Fn = std::remove_reference_t<F>;
    auto* p = const_cast<std::remove_const_t<Fn>*>(&fn);
    run(
        n, grain, [](void* c, int b, int e, int w) { (*static_cast<Fn*>(c))(b, e, w); }, p);
  }

 private:
  using Call = void (*)(void*, int, int, int);
  void run(int n, int grain, Call call, void* context);
  // Runs the current job's chunks until none is left; returns what one threw.
  std::exception_ptr take_chunks(int worker);
  void worker_loop(int worker);
  void stop_and_join();

  int num_workers_ = 1;
  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  // Atomic so that a worker between jobs, and the caller waiting for the
  // workers, may watch them for a moment without the mutex (kSpin).
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<int> remaining_{0};
  bool stop_ = false;
  int job_n_ = 0;
  int job_grain_ = 1;
  std::atomic<int> next_{0};  // the job's first index no worker has taken
  Call job_call_ = nullptr;
  void* job_context_ = nullptr;
  std::exception_ptr error_;
};

}  // namespace arttrack
