#pragma once
// `enact experiment` run in the background for the experiment command-line tests: a script
// types on its stdin (a person at the terminal), the terminal is read back; and CSV rows.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/test_util.h"

namespace enact::test {

// `enact experiment ARGS...` in the background: stdin a pipe the test writes to, stdout
// and stderr into files
class Experiment {
 public:
  Experiment(const TempDir& dir, std::vector<std::string> args) : out_(dir.file("run.out")), err_(dir.file("run.err")) {
    args.insert(args.begin(), {ENACT_CLI, "experiment"});
    int in[2];
    if (pipe(in) != 0) throw std::runtime_error("pipe failed");
    pid_ = fork();
    if (pid_ == 0) {
      dup2(in[0], 0);
      close(in[0]);
      close(in[1]);
      const int o = open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644), e = open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(o, 1);
      dup2(e, 2);
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(in[0]);
    stdin_ = in[1];
  }
  ~Experiment() {
    if (stdin_ >= 0) close(stdin_);
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      wait_exit(10.0);
    }
  }

  void type(const std::string& text) { ASSERT_EQ(write(stdin_, text.data(), text.size()), static_cast<ssize_t>(text.size())); }
  void signal(int sig) { kill(pid_, sig); }
  std::string terminal() const { return read_file_or_empty(err_); }

  // waits until the terminal shows `needle` `count` times; false on timeout or exit
  bool wait_for(const std::string& needle, int count, double timeout_s) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < end) {
      const std::string t = terminal();
      int seen = 0;
      for (auto at = t.find(needle); at != std::string::npos; at = t.find(needle, at + 1)) ++seen;
      if (seen >= count) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  // its exit code (128 + signal), or -1 after timeout_s
  int wait_exit(double timeout_s) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    int status = 0;
    while (std::chrono::steady_clock::now() < end) {
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }

 private:
  std::string out_, err_;
  pid_t pid_ = -1;
  int stdin_ = -1;
};

// the rows of a CSV file, split at commas, the header first
inline std::vector<std::vector<std::string>> csv_rows(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

}  // namespace enact::test
