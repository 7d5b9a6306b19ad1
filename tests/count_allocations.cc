// The allocation counter of count_allocations.h: the global operator new and
// delete replaced, once in the program that links it (tracker_tests, every
// test of it). Every unaligned form is replaced, nothrow and array ones
// included, so that each block is freed by the allocator that made it (a
// sanitizer build reports a nothrow new of its own freed by our delete as
// a mismatch); the aligned forms stay the library's, paired among
// themselves. malloc, calloc and realloc are counted through the linker's
// --wrap=SYMBOL (tests/CMakeLists.txt): every call from the program's own
// objects and static libraries (Eigen's dynamic matrices, inlined into the
// tracker's) goes to __wrap_SYMBOL, which counts and calls the real one.
#include "count_allocations.h"

#include <cstdlib>
#include <new>

// The replaced operators pair malloc with free; GCC 12 inlines them into
// callers and then warns that free meets a pointer from operator new.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

std::atomic<long> g_allocations{0};

extern "C" {
void* __real_malloc(std::size_t size);
void* __real_calloc(std::size_t count, std::size_t size);
void* __real_realloc(void* p, std::size_t size);
void* __wrap_malloc(std::size_t size) {
  ++g_allocations;
  return __real_malloc(size);
}
void* __wrap_calloc(std::size_t count, std::size_t size) {
  ++g_allocations;
  return __real_calloc(count, size);
}
void* __wrap_realloc(void* p, std::size_t size) {
  ++g_allocations;
  return __real_realloc(p, size);
}
}

namespace {

// malloc is the wrapped one: it counts.
void* counted_malloc(std::size_t size) noexcept { return std::malloc(size ? size : 1); }

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
