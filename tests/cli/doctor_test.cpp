// enact doctor: one line per check; a machine where the loop cannot lock memory or use
// SCHED_FIFO (here: the same machine, as an unprivileged user with both limits at 0) fails.
#include <unistd.h>

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/rt/probe.h"
#include "core/rt/profile.h"
#include "tests/cli/cli_support.h"

namespace enact::test {
namespace {

const char* const kChecks[] = {"memlock", "sched_fifo", "cpu_governor", "cpu_idle", "cpu_latency", "isolated_cpus",
                               "timer_slack", "rt_throttling", "usb_udev", "brltty", "display", "nodejs"};

// the line of check `name`, "" when absent
std::string line_of(const std::string& out, const std::string& name) {
  const auto at = out.find("  " + name + " ");
  if (at == std::string::npos) return "";
  const auto begin = out.rfind('\n', at) == std::string::npos ? 0 : out.rfind('\n', at) + 1;
  return out.substr(begin, out.find('\n', at) - begin);
}

TEST(Doctor, OneLinePerCheckAndExitFollowsTheBlockingOnes) {
  const RunResult r = enact("doctor");
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;
  bool failed = false;
  for (const char* name : kChecks) {
    const std::string line = line_of(r.out, name);
    ASSERT_FALSE(line.empty()) << name << " missing:\n" << r.out;
    EXPECT_TRUE(line.starts_with("ok") || line.starts_with("warn") || line.starts_with("FAIL")) << line;
    failed = failed || line.starts_with("FAIL");
  }
  EXPECT_EQ(r.exit_code, failed ? 1 : 0) << r.out;
  // what it says about Node.js is what the shell finds
  EXPECT_EQ(line_of(r.out, "nodejs").starts_with("ok"), run("command -v node").exit_code == 0);
}

TEST(Doctor, NoMemoryLockingAndNoRealtimePriorityBlockTheLoop) {
  // limits of 64 KiB and priority 0 bind only an unprivileged user: drop root when we are it
  const std::string drop = geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups --inh-caps=-all " : "";
  if (!drop.empty() && run("command -v setpriv").exit_code != 0) GTEST_SKIP() << "running as root without setpriv: cannot drop privileges";
  const RunResult r = run(drop + "bash -c 'ulimit -l 64; ulimit -r 0; " + ENACT_CLI + " doctor'");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_TRUE(line_of(r.out, "memlock").starts_with("FAIL")) << r.out;
  EXPECT_TRUE(line_of(r.out, "sched_fifo").starts_with("FAIL")) << r.out;
  EXPECT_NE(line_of(r.out, "memlock").find("fix:"), std::string::npos);
}

// a probe of this boot with the given figures, in a cache folder of its own (XDG_CACHE_HOME)
std::string cached_machine(const TempDir& dir, std::int64_t sleep_p99_ns, std::int64_t fifo_p99_ns) {
  rt::MachineProbe p;
  std::ifstream("/proc/sys/kernel/random/boot_id") >> p.boot_id;
  p.cpus = static_cast<int>(rt::system_calls().allowed_cpus().size());
  p.sleep_late = {sleep_p99_ns / 2, sleep_p99_ns, sleep_p99_ns * 2, 1000};
  p.sleep_late_fifo = {fifo_p99_ns / 2, fifo_p99_ns, fifo_p99_ns * 2, 1000};
  p.fifo_permitted = true;
  p.pipe_same_cpu = {4'000, 6'000, 40'000, 2000};
  p.pipe_cross_cpu = {25'000, 60'000, 900'000, 1000};
  std::filesystem::create_directories(dir.path() + "/enact");
  std::ofstream(dir.path() + "/enact/machine-probe") << rt::to_text(p);
  return "XDG_CACHE_HOME=" + dir.path() + " ";
}

// the machine section: the probe's figures, the rate each mode holds from them, and what to
// change, read from this boot's probe (here a crafted one, so that the advice is checked)
TEST(Doctor, SaysWhatThisMachinesFiguresHoldAndWhatToChange) {
  {
    TempDir dir;
    // a VM that wakes 90 us late, FIFO no sooner
    const RunResult r = run(cached_machine(dir, 90'000, 88'000) + ENACT_CLI + " doctor");
    EXPECT_NE(r.out.find("normal scheduling: late p50 45.0 us, p99 90.0 us"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("pipe round trip between two threads on one CPU: p50 4.0 us"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("a sleeping thread wakes 90 us late (p99)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("SCHED_FIFO wakes no sooner here"), std::string::npos) << r.out;
    // 2 x (90 x 1.25 + 5) us and the tick: under 5 kHz
    EXPECT_NE(r.out.find("a sleeping loop cannot hold 5 kHz here"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("ready for the real-time loop"), std::string::npos) << r.out;
  }
  {
    TempDir dir;
    // a machine that wakes 5 us late, FIFO at 3 us
    const RunResult r = run(cached_machine(dir, 5'000, 3'000) + ENACT_CLI + " doctor");
    EXPECT_NE(r.out.find("co-located (enact-rt), sleeping each tick: up to "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("wakes no sooner"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("cannot hold 5 kHz"), std::string::npos) << r.out;
  }
}

}  // namespace
}  // namespace enact::test
