// Counts heap allocations, for the tests that check that a hot path (forward
// kinematics, rendering, the reported covariance's update) allocates
// nothing: compare g_allocations before and after. count_allocations.cc
// replaces the global operator new and delete in the test program that
// links it (tracker_tests), and counts malloc, calloc and realloc, which
// Eigen's dynamic matrices call directly, through the linker's --wrap
// (tests/CMakeLists.txt).
#pragma once

#include <atomic>

extern std::atomic<long> g_allocations;
