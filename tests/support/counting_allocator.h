// SPDX-License-Identifier: GPL-3.0-or-later
// Counts heap allocations: replaces the global operator new/delete with malloc-based ones that count while
// dtf::test::counting is set. Include it in exactly one source file of a test executable.
#pragma once

// GCC 12 pairs an inlined `new T` in a test with this file's free() and warns of a mismatch (with -Werror,
// fails the build) when the optimiser sees through the replacements; both sides are replaced here, over
// malloc and free, so the pair matches.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

#include <atomic>
#include <cstdlib>
#include <new>

namespace dtf::test {
// Allocations counted while `counting` is set.
inline std::atomic<long> allocations{0};
inline std::atomic<bool> counting{false};
} // namespace dtf::test

// Every replaceable form that allocates with malloc is replaced, so that each pointer is freed by the
// allocator that made it: with only the plain forms replaced, a nothrow new (std::stable_sort's temporary
// buffer) came from ASan's operator new and was released by the free() below (alloc-dealloc-mismatch).
// Aligned forms are left to the library: they pair among themselves.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (dtf::test::counting.load(std::memory_order_relaxed)) dtf::test::allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n ? n : 1);
}
void* operator new(std::size_t n) {
  if (void* p = operator new(n, std::nothrow)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  return operator new(n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  return operator new(n, std::nothrow);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
