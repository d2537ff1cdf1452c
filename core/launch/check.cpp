#include "core/launch/check.h"

#include "core/config/env.h"
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>

namespace enact::launch {
namespace {

// how long a node may take to check its parameters (it loads its scene and models)
constexpr int kCheckTimeout_ms = 20000;

// runs `argv` with `env` added, its stdout discarded; its exit status and stderr
std::pair<int, std::string> run_check(const std::vector<std::string>& argv, const std::vector<Param>& env) {
  int err[2];
  if (pipe2(err, O_CLOEXEC) != 0) return {-1, "cannot create a pipe"};
  const pid_t pid = fork();
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(err[1], 2);
    unsetenv(env::kReadyFd);
    for (const Param& e : env) setenv(e.name.c_str(), e.value.c_str(), 1);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  close(err[1]);
  std::string text;
  char buf[512];
  for (ssize_t n; (n = read(err[0], buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR);) {
    if (n > 0) text.append(buf, static_cast<std::size_t>(n));
  }
  close(err[0]);
  // stderr closed: it has exited, or is about to
  int status = 0;
  for (int waited_ms = 0; waitpid(pid, &status, WNOHANG) != pid; waited_ms += 10) {
    if (waited_ms >= kCheckTimeout_ms) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return {-1, "did not finish its check within " + std::to_string(kCheckTimeout_ms / 1000) + " s"};
    }
    const timespec ten_ms{0, 10'000'000};
    nanosleep(&ten_ms, nullptr);
  }
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text};
}

}  // namespace

bool checkable(const NodeSpec& node) {
  const std::string file = std::filesystem::path(node.path).filename().string();
  if (file == "enact") return !node.args.empty() && node.args[0] == "play";
  return file == "enact-sim" || file == "enact-rt" || file == "enact-ffd" || file == "enact-tactile" || file == "enact-logger" || file == "enact-foxglove";
}

std::vector<std::string> check_nodes(const LaunchDescription& graph) {
  std::vector<std::string> problems;
  for (const NodeSpec& n : graph.nodes) {
    if (!checkable(n)) continue;
    std::vector<std::string> argv = n.argv();
    argv.push_back("--check");
    auto [code, said] = run_check(argv, n.env);
    if (code == 0) continue;
    while (!said.empty() && said.back() == '\n') said.pop_back();
    problems.push_back(n.source + ": node '" + n.name + "': " + (said.empty() ? "its check failed (exit " + std::to_string(code) + ")" : said));
  }
  return problems;
}

}  // namespace enact::launch
