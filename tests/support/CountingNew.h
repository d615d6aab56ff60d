// Heap allocations counted while g_countAllocations is set: this header replaces the binary's
// operator new and delete, so include it in exactly one file of a test binary
// (events_reporting_test, spacegame_test). gcc takes the replaced pair, once inlined, for
// malloc freed by delete: it is not.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

static std::atomic<long> g_allocations{0};
static std::atomic<bool> g_countAllocations{false};
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t n) {
  if (g_countAllocations) ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
