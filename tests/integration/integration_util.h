#pragma once
// Helpers of the integration tests: the real `enact launch` started in the background on a
// real launch file, its log polled, and an observer on the graph's attach point.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <optional>
#include <regex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/bus/bytes.h"
#include "core/bus/client.h"
#include "core/bus/typed.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/graph.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"
#include "tests/support/test_util.h"

namespace enact::test {

using Clock = std::chrono::steady_clock;

// how long a graph may take to say it is ready: only keeps a broken program from hanging a test
inline constexpr double kReadyTimeout_s = 20.0;
// the enact command line of this build
inline const std::string kCli = ENACT_CLI;

inline Clock::time_point after(double seconds) {
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

inline double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// a loopback TCP port free right now: bind port 0, read it, close (a small race with other
// programs picking the same port; acceptable on a test machine)
inline int free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) throw std::runtime_error("socket() failed");
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
    close(fd);
    throw std::runtime_error("cannot bind a loopback port");
  }
  const int port = ntohs(addr.sin_port);
  close(fd);
  return port;
}

inline bool process_gone(pid_t pid) { return kill(pid, 0) == -1 && errno == ESRCH; }

// whether `pid` is gone within timeout_s (polled every 20 ms)
inline bool gone_within(pid_t pid, double timeout_s) {
  const auto end = after(timeout_s);
  while (!process_gone(pid) && Clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  return process_gone(pid);
}

// starts argv[0] (a path) in the background, stdout and stderr into the files `out` and
// `err`, with `env` entries ("NAME=VALUE") added to its environment; its pid
inline pid_t spawn(std::vector<std::string> argv, const std::string& out, const std::string& err, const std::vector<std::string>& env = {}) {
  std::vector<char*> cargv;
  for (auto& a : argv) cargv.push_back(a.data());
  cargv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    for (const std::string& e : env) putenv(const_cast<char*>(e.c_str()));
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0) _exit(126);
    dup2(o, 1);
    dup2(e, 2);
    execv(cargv[0], cargv.data());
    _exit(127);
  }
  return pid;
}

// SIGCONT on scope exit: a failed assertion must not leave a process stopped
struct Continue {
  pid_t pid;
  ~Continue() { kill(pid, SIGCONT); }
};

// `enact launch FILE --duration D --attach ENDPOINT [--arg K=V]...` in the background (fork
// and exec), stdout and stderr into files of `dir`. The destructor makes sure it is gone
// (SIGTERM, then SIGKILL; its nodes die with it: PR_SET_PDEATHSIG in the supervisor).
class Launcher {
 public:
  // `endpoint`: the attach point's ("" : a free loopback port); `options`: more options of
  // `enact launch` (e.g. --access FILE)
  Launcher(const TempDir& dir, const std::string& file, double duration_s, const std::vector<std::string>& launch_args = {},
           const std::string& endpoint = "", const std::vector<std::string>& options = {})
      : out_(dir.file("launcher.out")), err_(dir.file("launcher.err")) {
    endpoint_ = endpoint.empty() ? "tcp://127.0.0.1:" + std::to_string(free_port()) : endpoint;
    std::vector<std::string> argv = {ENACT_CLI, "launch", file, "--duration", std::to_string(duration_s), "--attach", endpoint_};
    for (const auto& a : launch_args) {
      argv.push_back("--arg");
      argv.push_back(a);
    }
    argv.insert(argv.end(), options.begin(), options.end());
    pid_ = spawn(argv, out_, err_);
  }
  ~Launcher() {
    if (pid_ > 0) stop(5.0);
  }
  Launcher(const Launcher&) = delete;
  Launcher& operator=(const Launcher&) = delete;

  pid_t pid() const { return pid_; }
  const std::string& endpoint() const { return endpoint_; }

  // the launcher's stdout so far (its nodes' summaries)
  std::string out() const {
    try {
      return read_file(out_);
    } catch (const std::exception&) {
      return "";
    }
  }

  // the launcher's stderr so far (its own log lines and its nodes')
  std::string log() const {
    try {
      return read_file(err_);
    } catch (const std::exception&) {
      return "";
    }
  }

  // polls the log until it contains `needle`; false on timeout or when the launcher exited
  bool wait_log(const std::string& needle, double timeout_s) {
    const auto end = after(timeout_s);
    while (Clock::now() < end) {
      if (log().find(needle) != std::string::npos) return true;
      if (pid_ > 0 && try_reap()) return log().find(needle) != std::string::npos;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  // the pid in the log line "started NODE (pid N)", or -1
  pid_t pid_of(const std::string& node) const {
    std::smatch m;
    const std::string text = log();
    if (std::regex_search(text, m, std::regex("started " + node + " \\(pid ([0-9]+)\\)"))) return static_cast<pid_t>(std::stol(m[1].str()));
    return -1;
  }

  // waits up to timeout_s for the launcher to exit by itself: its exit code, 128 + signal,
  // or nullopt (still running)
  std::optional<int> wait_exit(double timeout_s) {
    const auto end = after(timeout_s);
    while (pid_ > 0) {
      if (try_reap()) break;
      if (Clock::now() >= end) return std::nullopt;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return code_;
  }

  // SIGTERM (a clean stop of the graph), up to timeout_s, then SIGKILL: the exit code as above
  int stop(double timeout_s = 10.0) {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      if (!wait_exit(timeout_s)) {
        kill(pid_, SIGKILL);
        int status = 0;
        waitpid(pid_, &status, 0);
        pid_ = -1;
        code_ = 128 + SIGKILL;
      }
    }
    return code_;
  }

 private:
  bool try_reap() {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) != pid_) return false;
    pid_ = -1;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    return true;
  }

  std::string out_, err_, endpoint_;
  pid_t pid_ = -1;
  int code_ = -1;
};

// everything an observer received, decoded, in arrival order per topic
struct Observed {
  std::vector<msgs::DeviceState> states;
  std::vector<msgs::ForceCommand> forces;
  std::vector<msgs::TactileFrame> frames;
  std::vector<msgs::TactileShown> shown;
  std::vector<msgs::SceneState> scenes;
  std::vector<msgs::TaskEvent> events;
  std::vector<msgs::NodeStatus> statuses;
  std::vector<msgs::GraphInfo> graphs;
};

// an observer of a graph: one SUB socket on the attach point, a typed subscriber per topic.
// Its receive queue is large (the attach point's observer side is lossy: a test process
// descheduled on a busy machine would otherwise lose messages).
class Observer {
 public:
  // `keys`: for a graph launched with --access (bus::attach_connect)
  explicit Observer(const std::string& endpoint, const bus::ClientKeys& keys = {}) {
    bytes_.set_receive_hwm(200000);
    if (keys.enabled()) bus::attach_connect(bytes_.socket(), endpoint, keys);
    else bytes_.connect(endpoint);
  }

  bus::ByteSubscriber& bytes() { return bytes_; }

  // subscriptions, made before observe()
  void all_topics() {
    states.emplace(bytes_, "ffd/state");
    forces.emplace(bytes_, "ffd/force");
    frames.emplace(bytes_, "tactile/frame");
    shown.emplace(bytes_, "tactile/shown");
    scenes.emplace(bytes_, "sim/scene");
    events.emplace(bytes_, "task/event");
    statuses.emplace(bytes_, "node/status");
    graphs.emplace(bytes_, "graph/topics");
  }

  // receives for `seconds`, appending what arrived to `out`; `each` (if any) sees every
  // valid message's topic after it was appended, and stops early by returning false
  template <class Each>
  void observe(double seconds, Observed& out, Each each) {
    const auto end = after(seconds);
    bus::RawMessage raw;
    while (Clock::now() < end) {
      const int left_ms = static_cast<int>(std::max<std::int64_t>(1, std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()).count()));
      if (!bytes_.receive(raw, std::min(left_ms, 50))) continue;
      const std::string_view t = raw.topic();
      bool ok = false;
      if (t == "ffd/state" && states) ok = take(*states, raw, out.states);
      else if (t == "ffd/force" && forces) ok = take(*forces, raw, out.forces);
      else if (t == "tactile/frame" && frames) ok = take(*frames, raw, out.frames);
      else if (t == "tactile/shown" && shown) ok = take(*shown, raw, out.shown);
      else if (t == "sim/scene" && scenes) ok = take(*scenes, raw, out.scenes);
      else if (t == "task/event" && events) ok = take(*events, raw, out.events);
      else if (t == "node/status" && statuses) ok = take(*statuses, raw, out.statuses);
      else if (t == "graph/topics" && graphs) ok = take(*graphs, raw, out.graphs);
      if (ok && !each(t)) return;
    }
  }
  void observe(double seconds, Observed& out) {
    observe(seconds, out, [](std::string_view) { return true; });
  }

  // the first node/status of `node` stamped after after_ns, within timeout_s (statuses must
  // be subscribed)
  std::optional<msgs::NodeStatus> status_after(Observed& seen, const std::string& node, std::int64_t after_ns, double timeout_s) {
    std::optional<msgs::NodeStatus> found;
    observe(timeout_s, seen, [&](std::string_view topic) {
      if (topic != "node/status") return true;
      const msgs::NodeStatus& s = seen.statuses.back();
      if (s.node() == node && s.header().stamp_ns() > after_ns) found = s;
      return !found;
    });
    return found;
  }

  std::optional<bus::Subscriber<msgs::DeviceState>> states;
  std::optional<bus::Subscriber<msgs::ForceCommand>> forces;
  std::optional<bus::Subscriber<msgs::TactileFrame>> frames;
  std::optional<bus::Subscriber<msgs::TactileShown>> shown;
  std::optional<bus::Subscriber<msgs::SceneState>> scenes;
  std::optional<bus::Subscriber<msgs::TaskEvent>> events;
  std::optional<bus::Subscriber<msgs::NodeStatus>> statuses;
  std::optional<bus::Subscriber<msgs::GraphInfo>> graphs;

 private:
  template <class Msg>
  static bool take(bus::Subscriber<Msg>& sub, const bus::RawMessage& raw, std::vector<Msg>& out) {
    Msg m;
    if (!sub.accept(raw, m)) return false;
    out.push_back(std::move(m));
    return true;
  }

  bus::ByteSubscriber bytes_;
};

// the scenes of a bridge run under CM1 checked against contact: every pin up exactly where
// its mass is in contact, a force pushing up while on the top, no force without contact. One
// exception, counted apart: where the force path was cut (a device fault, a late tick), the
// body is re-synchronised onto the surface it touches, with no force at all until the path is
// whole again; a test bounds those scenes by the faults it saw.
struct ContactCheck {
  int on_top = 0;         // scenes on the top surface
  int resting = 0;        // of them, touching it with no force anywhere (a re-synchronised body)
  int bad = 0;            // scenes that break a rule
  std::string first_bad;  // the first of them, as text
};
inline ContactCheck check_follows_contact(const std::vector<msgs::SceneState>& scenes) {
  const auto zero = [](const msgs::Vec3& v) { return v.x() == 0.0 && v.y() == 0.0 && v.z() == 0.0; };
  ContactCheck c;
  for (const auto& s : scenes) {
    bool any = false, ok = s.pin_level_size() == 16;
    for (int i = 0; ok && i < 16; ++i) {
      any = any || s.in_contact(i);
      ok = s.pin_level(i) == (s.in_contact(i) ? 1.0f : 0.0f);
    }
    if (s.on_top()) {
      ++c.on_top;
      const bool no_force = zero(s.resultant_force()) && std::all_of(s.contact_force().begin(), s.contact_force().end(), zero);
      if (no_force) ++c.resting;
      ok = ok && (no_force || s.resultant_force().z() > 0.0);
    }
    if (!any) ok = ok && zero(s.resultant_force());
    c.bad += !ok;
    if (!ok && c.first_bad.empty()) c.first_bad = s.ShortDebugString();
  }
  return c;
}

}  // namespace enact::test
