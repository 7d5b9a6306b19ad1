// The allocation counter of count_allocations.h: the global operator new and
// delete replaced, once in the program that links it (tracker_tests, every
// test of it). Every unaligned form is replaced, nothrow and array ones
// included, so that each block is freed by the allocator that made it (a
// sanitizer build reports a nothrow new of its own freed by our delete as
// a mismatch); the aligned forms stay the library's, paired among
// themselves.
#include "count_allocations.h"

#include <cstdlib>
#include <new>

// The replaced operators pair malloc with free; GCC 12 inlines them into
// callers and then warns that free meets a pointer from operator new.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

std::atomic<long> g_allocations{0};

namespace {

void* counted_malloc(std::size_t size) noexcept {
  ++g_allocations;
  return std::malloc(size ? size : 1);
}

void* counted_malloc_or_throw(std::size_t size) {
  if (void* p = counted_malloc(size)) return p;
  throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t size) { return counted_malloc_or_throw(size); }
void* operator new[](std::size_t size) { return counted_malloc_or_throw(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return counted_malloc(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return counted_malloc(size);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
