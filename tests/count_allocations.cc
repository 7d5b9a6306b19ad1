// The allocation counter of count_allocations.h: the global operator new and
// delete replaced, once in the program that links it.
#include "count_allocations.h"

#include <cstdlib>
#include <new>

// The replaced operators pair malloc with free; GCC 12 inlines them into
// callers and then warns that free meets a pointer from operator new.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

std::atomic<long> g_allocations{0};

void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
