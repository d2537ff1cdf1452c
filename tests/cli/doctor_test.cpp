// enact doctor: one line per check; a machine where the loop cannot lock memory or use
// SCHED_FIFO (here: the same machine, as an unprivileged user with both limits at 0) fails.
#include <unistd.h>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace enact::test
