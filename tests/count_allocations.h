// Counts heap allocations, for the tests that check that a hot path (forward
// kinematics, rendering) allocates nothing: compare g_allocations before and
// after. It replaces the global operator new and delete, so include it in one
// file of a test program only.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

// The replaced operators pair malloc with free; GCC 12 inlines them into
// callers and then warns that free meets a pointer from operator new.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
static std::atomic<long> g_allocations{0};
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
