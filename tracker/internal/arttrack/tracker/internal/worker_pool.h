// Worker threads kept alive between calls, to split a loop over particles
// across cores (the particle filter's evaluations, the hypothesis
// evaluator's renders). Kept out of the filter's and the configuration's
// headers so that they need no <thread> or <mutex>.
#pragma once

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

  // Calls fn(begin, end, worker) for the contiguous chunks of [0, n),
  // chunk w = [n w / W, n (w+1) / W) on worker w in [0, W) (the caller is
  // worker 0), and returns when all are done. An exception thrown by fn is
  // rethrown here. Does not allocate.
  template <class F>
  void parallel_for(int n, F&& fn) {
    using Fn = std::remove_reference_t<F>;
    auto* p = const_cast<std::remove_const_t<Fn>*>(&fn);
    run(
        n, [](void* c, int b, int e, int w) { (*static_cast<Fn*>(c))(b, e, w); }, p);
  }

 private:
  using Call = void (*)(void*, int, int, int);
  void run(int n, Call call, void* context);
  void worker_loop(int worker);
  void stop_and_join();

  int num_workers_ = 1;
  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  std::uint64_t generation_ = 0;
  int remaining_ = 0;
  bool stop_ = false;
  int job_n_ = 0;
  Call job_call_ = nullptr;
  void* job_context_ = nullptr;
  std::exception_ptr error_;
};

}  // namespace arttrack
