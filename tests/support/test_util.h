#pragma once
// Test helpers: temporary directories, files, bounded waits, and running the enact command
// line. Refusals (the message of a config::Error): tests/support/refusal.h.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <thread>

#include "core/graph/temp_folder.h"

namespace enact::test {

inline constexpr std::int64_t kMs = 1'000'000;  // one millisecond, in ns

// a fresh directory under $TMPDIR (enact-test-XXXXXX), removed with everything in it when
// destroyed: the project's TempFolder with a test prefix
class TempDir : public graph::TempFolder {
 public:
  TempDir() : TempFolder((std::filesystem::temp_directory_path() / "enact-test-").string()) {}
  std::string file(const std::string& name) const { return path() + "/" + name; }
};

// true as soon as `done()` holds, polling every poll_ms; false when it did not within
// timeout_s (a bound that only keeps a broken program from hanging the suite: nothing timed)
template <class Done>
bool eventually(Done&& done, double timeout_s = 10.0, int poll_ms = 1) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(poll_ms));
  }
  return true;
}

void write_file(const std::string& path, const std::string& text);
std::string read_file(const std::string& path);
// the file's text, "" when it cannot be read (not written yet)
std::string read_file_or_empty(const std::string& path);

struct RunResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// run a shell command line, capturing stdout and stderr
RunResult run(const std::string& command_line);

// a path under the source tree
std::string source_path(const std::string& relative);

}  // namespace enact::test
