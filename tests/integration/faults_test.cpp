// Faults on the distributed graph (launch/bridge.yaml at 5 kHz, simulated devices), as a
// lab would meet them: a stopped launcher (Ctrl-Z, a debugger), a killed launcher. The loop
// must not notice an observer's trouble, and the force and the pins must end safe.
//
// Machine assumptions: 2 noisy shared cores; bounds are generous, the figures are printed.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

constexpr double kReadyTimeout_s = 20.0;
constexpr double kRate_hz = 5000.0;  // bridge.yaml's

// SIGCONT on scope exit: a failed assertion must not leave a process stopped
struct Continue {
  pid_t pid;
  ~Continue() { kill(pid, SIGCONT); }
};

// the first node/status of `node` stamped after after_ns, within timeout_s
std::optional<msgs::NodeStatus> status_after(Observer& obs, Observed& seen, const std::string& node, std::int64_t after_ns, double timeout_s) {
  std::optional<msgs::NodeStatus> found;
  obs.observe(timeout_s, seen, [&](std::string_view topic) {
    if (topic != "node/status") return true;
    const msgs::NodeStatus& s = seen.statuses.back();
    if (s.node() == node && s.header().stamp_ns() > after_ns) found = s;
    return !found;
  });
  return found;
}

// the launcher, and with it the attach point, stopped for 3 s: the loop goes on answering
// (the attach point's copy of the traffic is lost alone, and counted by the observer)
TEST(Faults, StoppedLauncherNeverStopsTheLoop) {
  constexpr double kStop_s = 3.0;
  TempDir dir;
  Launcher launcher(dir, source_path("launch/bridge.yaml"), 60.0);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  Observer obs(launcher.endpoint());
  obs.states.emplace(obs.bytes(), "ffd/state");
  obs.statuses.emplace(obs.bytes(), "node/status");
  Observed seen;
  // the driver's cumulative count of samples without an answer in time, before
  const auto before = status_after(obs, seen, "ffd", 0, 5.0);
  ASSERT_TRUE(before) << "no node/status from ffd";

  // stop the launcher (its attach point thread and its ZeroMQ I/O thread with it)
  {
    Continue guard{launcher.pid()};
    ASSERT_EQ(kill(launcher.pid(), SIGSTOP), 0);
    std::this_thread::sleep_for(std::chrono::duration<double>(kStop_s));
  }
  const std::int64_t resumed_ns = bus::monotonic_ns();
  const auto after = status_after(obs, seen, "ffd", resumed_ns, 5.0);
  ASSERT_TRUE(after) << "no node/status from ffd after the launcher resumed\n" << launcher.log();

  // the loop answered (nearly) every sample of the window, and no watchdog episode was long
  const double window_s = static_cast<double>(after->header().stamp_ns() - before->header().stamp_ns()) * 1e-9;
  const double samples = window_s * kRate_hz;
  const std::uint64_t unanswered = after->faults() - before->faults();
  std::printf("[ measure ] launcher stopped %.1f s: %llu of %.0f samples without an answer in time; watchdog episodes %llu, longest %.3f s\n",
              kStop_s, static_cast<unsigned long long>(unanswered), samples, static_cast<unsigned long long>(after->watchdog_episodes()),
              after->watchdog_longest_s());
  EXPECT_GT(window_s, kStop_s);
  // (a blocked loop leaves the 3 s of the stop, 3/4 of the window, unanswered; a busy
  // machine alone misses a few %)
  EXPECT_LT(static_cast<double>(unanswered), 0.25 * samples) << "the loop stopped answering while the launcher was stopped";
  EXPECT_LT(after->watchdog_longest_s(), 0.5) << "the force was cut while the launcher was stopped";

  // the observer lost what the stopped attach point could not hold, and counts exactly that
  ASSERT_GE(seen.states.size(), 2u);
  const bus::TopicCounters c = obs.states->counters();
  const std::uint64_t span = seen.states.back().header().seq() - seen.states.front().header().seq() + 1;
  std::printf("[ measure ] observer: ffd/state %llu received, %llu lost in %llu gaps, seq span %llu\n", static_cast<unsigned long long>(c.received),
              static_cast<unsigned long long>(c.lost), static_cast<unsigned long long>(c.gaps), static_cast<unsigned long long>(span));
  EXPECT_GT(c.lost, 0u) << "nothing lost: the launcher was not stopped long enough to test anything";
  EXPECT_EQ(c.received + c.lost, span);
  EXPECT_EQ(launcher.stop(), 0) << launcher.log();
}

// the launcher killed by SIGKILL: every node stops cleanly (SIGTERM from the kernel), the
// FFD driver zeroing the force and the tactile driver lowering the pins
TEST(Faults, KilledLauncherZeroesTheForceAndLowersThePins) {
  ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  TempDir dir;
  Launcher launcher(dir, source_path("launch/bridge.yaml"), 60.0);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  const pid_t sim = launcher.pid_of("sim"), tactile = launcher.pid_of("tactile"), ffd = launcher.pid_of("ffd");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(kill(launcher.pid(), SIGKILL), 0);
  ASSERT_TRUE(launcher.wait_exit(5.0));
  const auto end = after(10.0);
  while (Clock::now() < end && !(process_gone(sim) && process_gone(tactile) && process_gone(ffd))) {
    while (waitpid(-1, nullptr, WNOHANG) > 0) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  prctl(PR_SET_CHILD_SUBREAPER, 0);
  EXPECT_TRUE(process_gone(sim) && process_gone(tactile) && process_gone(ffd)) << launcher.log();
  // the nodes' own last words (they share the launcher's stderr)
  const std::string log = launcher.log();
  EXPECT_NE(log.find("watchdog episode"), std::string::npos) << log;
  EXPECT_NE(log.find("force at exit: zeroed before the device was switched off"), std::string::npos) << log;
  EXPECT_NE(log.find("pins lowered."), std::string::npos) << log;
  EXPECT_NE(log.find("sim: "), std::string::npos) << log;
}

}  // namespace
}  // namespace enact::test
