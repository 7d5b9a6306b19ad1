// The worker pool under a limit of the system: tests/unsanitized, because
// AddressSanitizer reserves terabytes of shadow address space at start, so an
// address-space limit cannot leave "room for a few stacks" under it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

#include <sys/resource.h>
#include <unistd.h>

#include "arttrack/tracker/internal/worker_pool.h"

namespace arttrack {
namespace {

// Starts kMaxWorkerThreads workers under an address-space limit that leaves
// room for a few thread stacks only; exits 0 when that is the documented
// error, 3 for another error, 4 when the limit did not bite.
[[noreturn]] void start_pool_beyond_the_address_space() {
  long pages = 0;
  std::ifstream("/proc/self/statm") >> pages;
  const rlim_t room = rlim_t(pages) * rlim_t(sysconf(_SC_PAGESIZE)) + (rlim_t(64) << 20);
  const rlimit limit{room, room};
  setrlimit(RLIMIT_AS, &limit);
  try {
    WorkerPool pool(kMaxWorkerThreads);
  } catch (const std::runtime_error& e) {
    std::_Exit(std::string(e.what()).find("cannot start worker thread") == 0 ? 0 : 3);
  }
  std::_Exit(4);
}

// A thread count the system cannot start is an error, not a deadlock or a
// std::terminate from threads destroyed unjoined. In a child process, so the
// limit does not reach the other tests.
TEST(WorkerPoolDeathTest, ThreadsTheSystemCannotStartAreAnError) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(start_pool_beyond_the_address_space(), ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace arttrack
