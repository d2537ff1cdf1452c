#pragma once
// A malloc-counting guard: counts the heap allocations made by this thread while it is
// alive, and those of any thread inside its marked real-time sections (malloc, calloc, realloc, aligned allocations; operator new goes through malloc).
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
  // allocations any thread made inside a real-time section (core/rt/rt_section.h) since the
  // program started: a whole node's loop, however its host runs it
  static std::size_t in_rt_sections();

 private:
  std::size_t start_;
  bool was_counting_;
};

}  // namespace enact::test
