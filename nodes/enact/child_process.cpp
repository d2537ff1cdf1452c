#include "nodes/enact/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <sys/prctl.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace enact::cli {

pid_t start_logged(const std::vector<std::string>& args, const std::string& log, bool die_with_parent) {
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    if (die_with_parent) {
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (getppid() != parent) _exit(143);  // the parent ended before the request took
    }
    sigset_t all;
    sigfillset(&all);
    sigprocmask(SIG_UNBLOCK, &all, nullptr);
    if (!log.empty()) {
      const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
      if (fd >= 0) {
        dup2(fd, 1);
        dup2(fd, 2);
      }
    }
    std::vector<std::string> copy = args;
    std::vector<char*> argv;
    for (auto& x : copy) argv.push_back(x.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    std::fprintf(stderr, "cannot run %s: %s\n", args[0].c_str(), std::strerror(errno));
    _exit(127);
  }
  if (pid < 0) throw std::runtime_error("cannot start " + args[0] + ": " + std::strerror(errno));
  return pid;
}

}  // namespace enact::cli
