#include "core/launch/supervisor.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/signalfd.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

#include "core/config/env.h"
#include "core/rt/clock.h"

namespace enact::launch {
namespace {

using rt::now_ns;

std::int64_t to_ns(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

// a running (or stopped) process of the graph
struct Child {
  const NodeSpec* spec = nullptr;
  pid_t pid = -1;
  int ready_fd = -1;     // read end of its ready pipe
  bool ready = false;
  std::string ready_buffer;
  std::size_t parsed = 0;      // ready_buffer's lines handled so far
  double wait_s = 0.0;         // what it said it waits for (extends its ready timeout)
  int status = 0;        // wait status once exited
  std::int64_t respawn_at_ns = 0;
  int respawns = 0;      // restarts so far
  bool hung = false;     // stopped because it hung: a failure, whatever its exit status
};

std::string describe(int status) {
  if (WIFEXITED(status)) return "exited with code " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return std::string("was killed by signal ") + strsignal(WTERMSIG(status));
  return "stopped";
}

// fork and exec one process with its ready pipe; its own process group, so that a terminal's
// Ctrl-C reaches only the launcher, which stops the graph in order
bool start(Child& c, const sigset_t& blocked, const std::vector<Param>& env, std::ostream& log) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    log << "enact launch: cannot create a pipe for '" << c.spec->name << "': " << std::strerror(errno) << "\n";
    return false;
  }
  const std::vector<std::string> args = c.spec->argv();
  const pid_t launcher = getpid();
  const std::string respawn = std::to_string(c.respawns);  // $ENACT_RESPAWN, 0: a first start
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    // the launcher gone (even by SIGKILL): a clean stop, so drivers zero the force and lower
    // the pins; a node that does not exit within its grace period kills itself (node.h)
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != launcher) _exit(127);
    sigprocmask(SIG_UNBLOCK, &blocked, nullptr);
    close(fds[0]);
    // the ready pipe on fd 3 (a single digit: shells accept it in >&$ENACT_READY_FD), kept across exec
    if (fds[1] == 3) fcntl(3, F_SETFD, 0);
    else dup2(fds[1], 3);
    setenv(env::kReadyFd, "3", 1);
    setenv(env::kRespawn, respawn.c_str(), 1);
    for (const Param& e : env) setenv(e.name.c_str(), e.value.c_str(), 1);
    for (const Param& e : c.spec->env) setenv(e.name.c_str(), e.value.c_str(), 1);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    dprintf(2, "enact launch: cannot run %s: %s\n", argv[0], std::strerror(errno));
    _exit(127);
  }
  close(fds[1]);
  if (pid < 0) {
    close(fds[0]);
    log << "enact launch: cannot start '" << c.spec->name << "': " << std::strerror(errno) << "\n";
    return false;
  }
  setpgid(pid, pid);
  c.pid = pid;
  c.ready_fd = fds[0];
  c.ready = false;
  c.ready_buffer.clear();
  c.parsed = 0;
  c.wait_s = 0.0;
  log << "enact launch: started " << c.spec->name << " (pid " << pid << ")\n";
  return true;
}

// read what a process wrote on its ready pipe, handling its declarations; true once it
// said "ready"
bool read_ready(Child& c, const SupervisorOptions& options) {
  char buf[256];
  const ssize_t n = read(c.ready_fd, buf, sizeof buf);
  if (n > 0) c.ready_buffer.append(buf, static_cast<std::size_t>(n));
  bool ready = false;
  for (std::size_t end; (end = c.ready_buffer.find('\n', c.parsed)) != std::string::npos; c.parsed = end + 1) {
    const std::string line = c.ready_buffer.substr(c.parsed, end - c.parsed);
    ready = ready || line == "ready";
    if (line.rfind("wait ", 0) == 0) c.wait_s = std::max(0.0, std::atof(line.c_str() + 5));
    const std::size_t space = line.find(' ', 6);
    if (line.rfind("topic ", 0) == 0 && space != std::string::npos && options.on_topic) {
      options.on_topic(*c.spec, line.substr(6, space - 6), line.substr(space + 1));
    }
  }
  if (n <= 0 || ready) {
    close(c.ready_fd);
    c.ready_fd = -1;
  }
  return ready || c.ready_buffer.find("ready\n") != std::string::npos;
}

// a stream buffer that passes on whole lines only, each in one write
class WholeLines final : public std::streambuf {
 public:
  explicit WholeLines(std::ostream& out) : out_(out) {}
  ~WholeLines() override { sync(); }

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    line_.push_back(traits_type::to_char_type(c));
    if (c == '\n') sync();
    return c;
  }
  int sync() override {
    if (line_.empty()) return 0;
    out_.write(line_.data(), static_cast<std::streamsize>(line_.size()));
    out_.flush();
    line_.clear();
    return 0;
  }

 private:
  std::ostream& out_;
  std::string line_;
};

struct Graph {
  std::vector<Child> children;
  int signal_fd = -1;
  sigset_t blocked{};
  std::ostream& log;
  const SupervisorOptions& options;

  // reap every exited child into `exited` (what it wrote on its ready pipe first still counts)
  void reap(std::vector<Child*>& exited) {
    int status = 0;
    pid_t pid = 0;
    while ((pid = waitpid(-1, &status, WNOHANG)) > 0) {
      for (Child& c : children) {
        if (c.pid != pid) continue;
        c.status = status;
        c.pid = -1;
        // what it wrote before it exited still counts
        while (c.ready_fd >= 0 && !c.ready) c.ready = read_ready(c, options);
        if (c.ready_fd >= 0) {
          close(c.ready_fd);
          c.ready_fd = -1;
        }
        exited.push_back(&c);
      }
    }
  }

  // SIGTERM, wait up to the timeout, then SIGKILL the whole process group
  void stop(Child& c, double timeout_s) {
    if (c.pid <= 0) return;
    const pid_t pid = c.pid;
    kill(-pid, SIGTERM);
    kill(-pid, SIGCONT);  // a stopped process (SIGSTOP, a hang) can then stop cleanly
    const std::int64_t deadline = now_ns() + to_ns(timeout_s);
    int status = 0;
    while (now_ns() < deadline) {
      if (waitpid(pid, &status, WNOHANG) == pid) {
        c.pid = -1;
        c.status = status;
        kill(-pid, SIGKILL);  // anything it left in its group
        log << "enact launch: stopped " << c.spec->name << "\n";
        return;
      }
      usleep(2000);
    }
    kill(-pid, SIGKILL);
    waitpid(pid, &status, 0);
    c.pid = -1;
    c.status = status;
    log << "enact launch: killed " << c.spec->name << " (no exit " << timeout_s << " s after SIGTERM)\n";
  }

  bool stop_requested() const { return options.stop && options.stop->load(); }

  // every process has exited and none is to be restarted: nothing is left of the graph
  bool all_gone() const {
    return std::all_of(children.begin(), children.end(), [](const Child& c) { return c.pid <= 0 && c.respawn_at_ns == 0; });
  }
  // a process whose last exit was not exit 0 (an error, a crash, a hang stopped)
  bool any_failed() const {
    return std::any_of(children.begin(), children.end(), [](const Child& c) { return !WIFEXITED(c.status) || WEXITSTATUS(c.status) != 0; });
  }

  void stop_all(double timeout_s) {
    for (auto it = children.rbegin(); it != children.rend(); ++it) stop(*it, timeout_s);
    for (Child& c : children) {
      if (c.ready_fd >= 0) close(c.ready_fd);
      c.ready_fd = -1;
    }
  }

  // stops the running processes named in `names` (they hang), adding them to `exited`
  void stop_hung(const std::vector<std::string>& names, double timeout_s, std::vector<Child*>& exited) {
    for (const std::string& name : names) {
      for (Child& c : children) {
        if (c.spec->name != name || c.pid <= 0) continue;
        log << "enact launch: '" << name << "' (" << c.spec->source << ") hangs: no node/status for a while, stopping it\n";
        stop(c, timeout_s);
        c.hung = true;
        exited.push_back(&c);
      }
    }
  }

  // a process exited: log it; a required one stops the graph (false), a respawning one is
  // scheduled again
  bool handle_exit(Child& c) {
    log << "enact launch: '" << c.spec->name << "' (" << c.spec->source << ") " << describe(c.status) << "\n";
    if (options.on_exit) options.on_exit(*c.spec, c.status);
    if (c.spec->required) {
      log << "enact launch: required process '" << c.spec->name << "' is gone, stopping the graph\n";
      return false;
    }
    if (c.spec->respawn) schedule_respawn(c);
    return true;
  }

  // the next restart of `c`, after a delay doubled at each restart; none past respawn_max
  void schedule_respawn(Child& c) {
    if (c.respawns >= c.spec->respawn_max) {
      log << "enact launch: '" << c.spec->name << "' was restarted " << c.respawns << " times (respawn_max " << c.spec->respawn_max
          << "): not restarting it again\n  fix: find why it exits in its output above; or raise respawn_max at " << c.spec->source << "\n";
      return;
    }
    const double delay_s = c.spec->respawn_delay_s * std::pow(2.0, c.respawns);
    ++c.respawns;
    c.respawn_at_ns = now_ns() + std::max<std::int64_t>(1, to_ns(delay_s));
    log << "enact launch: restarting '" << c.spec->name << "' in " << delay_s << " s (restart " << c.respawns << " of " << c.spec->respawn_max
        << ")\n";
  }

  // wait for `c` to say ready; false on timeout, exit, or a stop signal (then `signalled`)
  bool wait_ready(Child& c, double timeout_s, bool& signalled) {
    std::int64_t deadline = now_ns() + to_ns(timeout_s);
    double extended_s = 0.0;
    while (!c.ready) {
      // a process that waits (for observers) has that long more
      if (c.wait_s > extended_s) {
        deadline = std::max(deadline, now_ns() + to_ns(timeout_s + c.wait_s));
        extended_s = c.wait_s;
      }
      const std::int64_t left_ms = (deadline - now_ns()) / 1'000'000;
      if (left_ms <= 0) {
        log << "enact launch: '" << c.spec->name << "' (" << c.spec->source << ") did not report ready within " << timeout_s + extended_s
            << " s\n  fix: check its output above; a node writes \"ready\" to $ENACT_READY_FD once active\n";
        return false;
      }
      if (stop_requested()) {
        signalled = true;
        return false;
      }
      pollfd fds[2] = {{signal_fd, POLLIN, 0}, {c.ready_fd, POLLIN, 0}};
      poll(fds, c.ready_fd >= 0 ? 2 : 1, static_cast<int>(std::min<std::int64_t>(left_ms, 100)));
      if (fds[0].revents & POLLIN) {
        signalfd_siginfo info{};
        if (read(signal_fd, &info, sizeof info) == sizeof info && info.ssi_signo != SIGCHLD) {
          signalled = true;
          return false;
        }
      }
      if (c.ready_fd >= 0 && (fds[1].revents & (POLLIN | POLLHUP))) c.ready = read_ready(c, options);
      std::vector<Child*> exited;
      reap(exited);
      for (Child* e : exited) {
        if (e == &c && !c.ready) {
          log << "enact launch: '" << c.spec->name << "' (" << c.spec->source << ") " << describe(c.status) << " before it was ready\n";
          return false;
        }
        if (!handle_exit(*e)) return false;
      }
    }
    log << "enact launch: " << c.spec->name << " ready\n";
    return true;
  }
};

}  // namespace

void block_supervisor_signals() {
  sigset_t blocked;
  sigemptyset(&blocked);
  sigaddset(&blocked, SIGINT);
  sigaddset(&blocked, SIGTERM);
  sigaddset(&blocked, SIGCHLD);
  sigprocmask(SIG_BLOCK, &blocked, nullptr);
}

int supervise(const LaunchDescription& graph, const SupervisorOptions& options, std::ostream& out) {
  // whole lines to `out`, each in one write: the nodes write to the same terminal or file, and
  // a line written piece by piece was split by theirs
  WholeLines lines(out);
  std::ostream log(&lines);
  // signals are read from a signalfd; children unblock them before exec
  sigset_t blocked;
  sigemptyset(&blocked);
  sigaddset(&blocked, SIGINT);
  sigaddset(&blocked, SIGTERM);
  sigaddset(&blocked, SIGCHLD);
  sigset_t previous;
  sigprocmask(SIG_BLOCK, &blocked, &previous);
  Graph g{{}, signalfd(-1, &blocked, SFD_CLOEXEC), blocked, log, options};
  for (const NodeSpec& n : graph.nodes) {
    Child c;
    c.spec = &n;
    g.children.push_back(c);
  }

  auto finish = [&](int code) {
    g.stop_all(options.stop_timeout_s);
    close(g.signal_fd);
    sigprocmask(SIG_SETMASK, &previous, nullptr);
    return code;
  };

  // start in order, each ready before the next
  for (Child& c : g.children) {
    bool signalled = false;
    if (!start(c, blocked, options.env, log)) return finish(1);
    if (!g.wait_ready(c, options.ready_timeout_s, signalled)) return finish(signalled ? 0 : 1);
  }
  log << "enact launch: graph ready (" << g.children.size() << " processes)\n";
  if (options.on_ready) options.on_ready();

  // supervise until a stop signal, the duration, or a required exit
  const std::int64_t end_ns = options.duration_s > 0.0 ? now_ns() + to_ns(options.duration_s) : INT64_MAX;
  while (true) {
    const std::int64_t now = now_ns();
    if (now >= end_ns) {
      log << "enact launch: duration reached, stopping\n";
      return finish(0);
    }
    for (Child& c : g.children) {
      if (c.pid > 0 || !c.spec->respawn || c.respawn_at_ns == 0 || now < c.respawn_at_ns) continue;
      c.respawn_at_ns = 0;
      bool signalled = false;
      if (!start(c, blocked, options.env, log) || !g.wait_ready(c, options.ready_timeout_s, signalled)) return finish(signalled ? 0 : 1);
    }
    if (g.stop_requested()) {
      log << "enact launch: stop requested, stopping\n";
      return finish(0);
    }
    pollfd fd{g.signal_fd, POLLIN, 0};
    poll(&fd, 1, 50);
    if (fd.revents & POLLIN) {
      signalfd_siginfo info{};
      if (read(g.signal_fd, &info, sizeof info) == sizeof info && info.ssi_signo != SIGCHLD) {
        log << "enact launch: " << strsignal(static_cast<int>(info.ssi_signo)) << ", stopping\n";
        return finish(0);
      }
    }
    std::vector<Child*> exited;
    if (options.hung_nodes) g.stop_hung(options.hung_nodes(), options.stop_timeout_s, exited);
    g.reap(exited);
    for (Child* c : exited) {
      // a required process that finished its job (exit 0, e.g. a replay at its end) ends
      // the graph successfully; a crash or an error fails it
      if (!g.handle_exit(*c)) return finish(!c->hung && WIFEXITED(c->status) && WEXITSTATUS(c->status) == 0 ? 0 : 1);
      c->hung = false;
    }
    // none was required, and each has ended (reaped here or while a restart waited for its
    // ready line): so has the graph (failed if one failed)
    if (g.all_gone()) {
      log << "enact launch: every process has exited, the graph ended\n";
      return finish(g.any_failed() ? 1 : 0);
    }
  }
}

}  // namespace enact::launch
