#pragma once
// A file-access guard: counts the files this thread opens while it is alive (open, openat,
// fopen and their 64-bit names: std::ifstream and every YAML or CSV reader go through them),
// beside the count of every thread since the program started. Linking this file into a test
// wraps those entry points of the program.
#include <cstddef>

namespace enact::test {

class FileGuard {
 public:
  FileGuard();
  ~FileGuard();
  FileGuard(const FileGuard&) = delete;
  FileGuard& operator=(const FileGuard&) = delete;
  // files this thread opened since the guard was made
  std::size_t opens() const;
  // files any thread opened since the program started
  static std::size_t opens_by_any_thread();
  // files any thread opened inside a real-time section (core/rt/rt_section.h)
  static std::size_t opens_in_rt_sections();

 private:
  std::size_t start_;
  bool was_counting_;
};

}  // namespace enact::test
