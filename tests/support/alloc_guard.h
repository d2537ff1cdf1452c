#pragma once
// A malloc-counting guard: counts the heap allocations made by this thread while it is
// alive (malloc, calloc, realloc, aligned allocations; operator new goes through malloc).
// Linking this file into a test replaces the allocator entry points of the program (under
// AddressSanitizer it counts through the sanitizer's allocation hook instead).
#include <cstddef>

namespace enact::test {

class AllocGuard {
 public:
  AllocGuard();
  ~AllocGuard();
  AllocGuard(const AllocGuard&) = delete;
  AllocGuard& operator=(const AllocGuard&) = delete;
  std::size_t allocations() const;

 private:
  std::size_t start_;
  bool was_counting_;
};

}  // namespace enact::test
