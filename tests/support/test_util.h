#pragma once
// Test helpers: temporary directories, files, and running the enact command line.
#include <string>

namespace enact::test {

// a fresh directory under $TMPDIR, removed with everything in it when destroyed
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

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
