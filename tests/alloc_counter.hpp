#pragma once
// Counts the heap allocations of a test executable (for "no heap per call" invariants).
// Include in exactly one .cpp file of a test executable: it replaces the global allocation
// functions. Every form that allocates with malloc is replaced (plain, array, nothrow; the
// sized deletes too), so memory never crosses between this allocator and another one (which
// AddressSanitizer reports as an alloc-dealloc mismatch).
#include <atomic>
#include <cstdlib>
#include <new>

namespace armstudy::test {
inline std::atomic<long> g_allocations{0};
inline void* countedAlloc(std::size_t n) noexcept {
  ++g_allocations;
  return std::malloc(n ? n : 1);
}
}  // namespace armstudy::test

void* operator new(std::size_t n) {
  if (void* p = armstudy::test::countedAlloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  if (void* p = armstudy::test::countedAlloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  return armstudy::test::countedAlloc(n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  return armstudy::test::countedAlloc(n);
}
// GCC sees through an inlined replaced new and delete and reports malloc-then-free as a mismatch
// of new and free: here that pairing is the point.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
#pragma GCC diagnostic pop
