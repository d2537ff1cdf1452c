// `enact launch` end to end: /bin/sh scripts as nodes, started in order, supervised, stopped
// in reverse order, and never outliving the launcher.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <sstream>
#include <streambuf>
#include <string>
#include <thread>
#include <vector>

#include "core/launch/launch_file.h"
#include "core/launch/supervisor.h"
#include "tests/support/test_util.h"

namespace enact::test {
namespace {

constexpr const char* kReady = "echo ready >&$ENACT_READY_FD";

// a launch-file node running `sh -c SCRIPT`, with extra `key: value` lines
std::string sh_node(const std::string& name, const std::string& script, const std::string& extra = "") {
  std::string yaml = "  - node:\n      name: " + name + "\n      exec: /bin/sh\n";
  std::string line;
  for (std::istringstream lines(extra); std::getline(lines, line);) yaml += "      " + line + "\n";
  yaml += "      args:\n        - \"-c\"\n        - |\n";
  for (std::istringstream lines(script); std::getline(lines, line);) yaml += "          " + line + "\n";
  return yaml;
}

bool exists(const std::string& path) { return std::filesystem::exists(path); }

bool gone(pid_t pid) { return kill(pid, 0) == -1 && errno == ESRCH; }

pid_t pid_in(const std::string& path) { return static_cast<pid_t>(std::stol(read_file(path))); }

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream ss(text);
  for (std::string line; std::getline(ss, line);) out.push_back(line);
  return out;
}

// where `needle` first appears in `text` (npos: never)
std::size_t at(const std::string& text, const std::string& needle) { return text.find(needle); }

bool has(const std::string& text, const std::string& needle) { return text.find(needle) != std::string::npos; }

// `enact launch FILE` started in the background by fork/exec, its output in files
class Launcher {
 public:
  Launcher(const TempDir& dir, const std::string& file) : out_(dir.file("launcher.out")), err_(dir.file("launcher.err")) {
    pid_ = fork();
    if (pid_ == 0) {
      dup2(open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644), 1);
      dup2(open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644), 2);
      execl(ENACT_CLI, ENACT_CLI, "launch", file.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~Launcher() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  Launcher(const Launcher&) = delete;
  Launcher& operator=(const Launcher&) = delete;

  pid_t pid() const { return pid_; }
  std::string log() const { return exists(err_) ? read_file(err_) : ""; }
  bool wait_for_log(const std::string& text, double timeout_s) const {
    return eventually([&] { return has(log(), text); }, timeout_s, 20);
  }
  // its wait status, or -1 when it did not exit within timeout_s
  int wait_exit(double timeout_s) {
    int status = -1;
    if (!eventually([&] { return waitpid(pid_, &status, WNOHANG) == pid_; }, timeout_s)) return -1;
    pid_ = -1;
    return status;
  }

 private:
  std::string out_;
  std::string err_;
  pid_t pid_ = -1;
};

class Launch : public ::testing::Test {
 protected:
  // writes launch.yaml from node entries and returns its path
  std::string launch_file(const std::string& nodes) {
    const std::string path = dir_.file("launch.yaml");
    write_file(path, "launch:\n" + nodes);
    return path;
  }
  RunResult launch(const std::string& nodes, const std::string& options) {
    return run(std::string(ENACT_CLI) + " launch " + launch_file(nodes) + " " + options);
  }
  std::string f(const std::string& name) const { return dir_.file(name); }
  TempDir dir_;
};

// a node that reports ready and runs until stopped
std::string idle(const std::string& pid_file = "/dev/null") {
  return "echo $$ > " + pid_file + "\n" + kReady + "\nwhile :; do sleep 0.05; done";
}

TEST_F(Launch, TwoNodesStartInOrderAndStopInReverse) {
  const RunResult r = launch(sh_node("first", idle()) + sh_node("second", idle()), "--duration 1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "graph ready")) << r.err;
  const std::size_t started_first = at(r.err, "started first"), started_second = at(r.err, "started second");
  const std::size_t stopped_first = at(r.err, "stopped first"), stopped_second = at(r.err, "stopped second");
  ASSERT_NE(started_first, std::string::npos) << r.err;
  ASSERT_NE(started_second, std::string::npos) << r.err;
  ASSERT_NE(stopped_first, std::string::npos) << r.err;
  ASSERT_NE(stopped_second, std::string::npos) << r.err;
  EXPECT_LT(started_first, started_second) << r.err;
  EXPECT_LT(started_second, at(r.err, "graph ready")) << r.err;
  EXPECT_LT(at(r.err, "graph ready"), stopped_second) << r.err;
  EXPECT_LT(stopped_second, stopped_first) << r.err;
  // the plan goes to stdout
  EXPECT_TRUE(has(r.out, "first: /bin/sh -c")) << r.out;
}

TEST_F(Launch, DurationRunEndsWithinGenerousBounds) {
  const auto start = std::chrono::steady_clock::now();
  const RunResult r = launch(sh_node("only", idle()), "--duration 1");
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GE(elapsed_s, 0.9);
  EXPECT_LT(elapsed_s, 10.0);
}

TEST_F(Launch, NodesGetACleanSigterm) {
  const std::string script = "trap 'echo term > " + f("term") + "; exit 0' TERM\n" + kReady + "\nwhile :; do sleep 0.05; done";
  const RunResult r = launch(sh_node("trapper", script), "--duration 0.5");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(exists(f("term"))) << r.err;
  EXPECT_EQ(read_file(f("term")), "term\n");
  EXPECT_TRUE(has(r.err, "stopped trapper")) << r.err;
}

TEST_F(Launch, ParamsArgsAndEnvReachTheProcess) {
  const std::string script = "echo \"$0 $1 $2 $3 $LEVEL\" > " + f("seen") + "\n" + kReady + "\nwhile :; do sleep 0.05; done";
  const RunResult r = launch(sh_node("p", script, "env: [{name: LEVEL, value: debug}]\nparam: [{name: k, value: v}]"),
                             "--duration 0.3");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(exists(f("seen"))) << r.err;
  EXPECT_EQ(read_file(f("seen")), "--name p --param=k=v  debug\n");
}

TEST_F(Launch, RequiredExitStopsTheGraphWithoutOrphans) {
  const RunResult r = launch(sh_node("other", idle(f("other.pid"))) +
                                 sh_node("core", std::string(kReady) + "\nsleep 0.3\nexit 3", "required: true"),
                             "--duration 8");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "'core'")) << r.err;
  EXPECT_TRUE(has(r.err, "exited with code 3")) << r.err;
  EXPECT_TRUE(has(r.err, "stopped other")) << r.err;
  EXPECT_FALSE(has(r.err, "duration reached")) << r.err;
  ASSERT_TRUE(exists(f("other.pid"))) << r.err;
  EXPECT_TRUE(gone(pid_in(f("other.pid"))));
}

TEST_F(Launch, NodeThatNeverReportsReadyFails) {
  const RunResult r = launch(sh_node("mute", "while :; do sleep 0.05; done"), "--ready-timeout 0.5");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "'mute'")) << r.err;
  EXPECT_TRUE(has(r.err, "ready")) << r.err;
  EXPECT_FALSE(has(r.err, "graph ready")) << r.err;
}

TEST_F(Launch, NodeThatExitsBeforeReadyFails) {
  const RunResult r = launch(sh_node("quitter", "exit 4"), "");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "'quitter'")) << r.err;
  EXPECT_TRUE(has(r.err, "exited with code 4 before it was ready")) << r.err;
}

TEST_F(Launch, RespawnRestartsANodeThatExits) {
  const std::string script = "echo start >> " + f("starts") + "\n" + kReady + "\nsleep 0.1\nexit 0";
  const RunResult r = launch(sh_node("flaky", script, "respawn: true\nrespawn_delay: 0.1"), "--duration 1.5");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(exists(f("starts"))) << r.err;
  EXPECT_GE(lines_of(read_file(f("starts"))).size(), 2u) << r.err;
}

// restarts stop at respawn_max, each after twice the previous delay, and the launcher says so
TEST_F(Launch, RespawnStopsAtRespawnMaxWithBackoff) {
  const std::string script = "echo start >> " + f("starts") + "\n" + kReady + "\nexit 3";
  const RunResult r = launch(sh_node("flaky", script, "respawn: true\nrespawn_delay: 0.05\nrespawn_max: 2"), "--duration 1.5");
  ASSERT_TRUE(exists(f("starts"))) << r.err;
  EXPECT_EQ(lines_of(read_file(f("starts"))).size(), 3u) << r.err;
  EXPECT_TRUE(has(r.err, "restarting 'flaky' in 0.05 s (restart 1 of 2)")) << r.err;
  EXPECT_TRUE(has(r.err, "restarting 'flaky' in 0.1 s (restart 2 of 2)")) << r.err;
  EXPECT_TRUE(has(r.err, "was restarted 2 times (respawn_max 2): not restarting it again")) << r.err;
  // then nothing is left of the graph: it ends, failed as its node did
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "every process has exited, the graph ended")) << r.err;
  EXPECT_FALSE(has(r.err, "duration reached")) << r.err;
}

// the launcher's own lines reach its output whole, each in one write: the nodes write to the
// same terminal or file, and a line written piece by piece was split by a node's line
// ("restarting 'sim' in ffd: watchdog: ...")
TEST_F(Launch, TheLaunchersLinesAreWrittenWhole) {
  struct Writes final : std::streambuf {
    std::vector<std::string> chunks;
    std::streamsize xsputn(const char* s, std::streamsize n) override {
      chunks.emplace_back(s, static_cast<std::size_t>(n));
      return n;
    }
    int_type overflow(int_type c) override {
      if (!traits_type::eq_int_type(c, traits_type::eof())) chunks.emplace_back(1, traits_type::to_char_type(c));
      return c;
    }
  };
  const std::string file = launch_file(sh_node("flaky", std::string(kReady) + "\nexit 3", "respawn: true\nrespawn_delay: 0.05\nrespawn_max: 1"));
  const launch::LaunchDescription graph = launch::load_launch(file, {});
  Writes writes;
  std::ostream out(&writes);
  launch::SupervisorOptions options;
  options.duration_s = 20.0;
  EXPECT_EQ(launch::supervise(graph, options, out), 1);
  ASSERT_GT(writes.chunks.size(), 4u);
  std::string all;
  for (const std::string& chunk : writes.chunks) {
    all += chunk;
    EXPECT_TRUE(!chunk.empty() && chunk.back() == '\n' && chunk.find('\n') == chunk.size() - 1) << "a piece of a line: [" << chunk << "]";
  }
  EXPECT_TRUE(has(all, "restarting 'flaky' in 0.05 s (restart 1 of 1)")) << all;
}

// processes none of which is required (a container that stops itself at its duration_s, a
// job that ends): once the last has exited the graph has ended, and so does the launcher, at
// once, failed when one of them failed; while one still runs, the graph goes on
TEST_F(Launch, AGraphEndsWhenTheLastOfItsProcessesHasExited) {
  const std::string early = std::string(kReady) + "\nsleep 0.2\nexit 0";
  const std::string later = std::string(kReady) + "\nsleep 0.8\necho done > " + f("later") + "\nexit 0";
  const auto began = std::chrono::steady_clock::now();
  const RunResult r = launch(sh_node("early", early) + sh_node("later", later), "--duration 60");
  const double took_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(exists(f("later"))) << "the graph went on after the first exit: " << r.err;
  EXPECT_TRUE(has(r.err, "every process has exited, the graph ended")) << r.err;
  EXPECT_FALSE(has(r.err, "duration reached")) << r.err;
  EXPECT_LT(took_s, 30.0) << "the launcher waited for its duration";
  const RunResult failed = launch(sh_node("early", early) + sh_node("broken", std::string(kReady) + "\nsleep 0.4\nexit 5"), "--duration 60");
  EXPECT_EQ(failed.exit_code, 1) << failed.err;
  EXPECT_TRUE(has(failed.err, "exited with code 5")) << failed.err;
  EXPECT_TRUE(has(failed.err, "every process has exited, the graph ended")) << failed.err;
}

// a node that writes "ready" and exits at once was ready: it is respawned, not a failed start
TEST_F(Launch, RespawnOfANodeThatExitsRightAfterReady) {
  const std::string script = "echo start >> " + f("starts") + "\n" + kReady + "\nexit 0";
  const RunResult r = launch(sh_node("flaky", script, "respawn: true\nrespawn_delay: 0.1"), "--duration 1.5");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(has(r.err, "before it was ready")) << r.err;
  ASSERT_TRUE(exists(f("starts"))) << r.err;
  EXPECT_GE(lines_of(read_file(f("starts"))).size(), 2u) << r.err;
}

// a respawning node that exits while a later node is still starting is respawned; the
// start goes on
TEST_F(Launch, RespawningNodeExitingWhileAnotherStarts) {
  const std::string flaky = std::string(kReady) + "\nsleep 0.1\nexit 0";
  const std::string slow = "sleep 0.6\n" + idle();
  const RunResult r = launch(sh_node("flaky", flaky, "respawn: true\nrespawn_delay: 0.1") + sh_node("slow", slow), "--duration 1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "graph ready")) << r.err;
}

TEST_F(Launch, KillingTheLauncherKillsItsChildren) {
  // orphans are re-parented to this process, which reaps them: a dead child is then truly gone
  ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  pid_t child = -1;
  {
    Launcher launcher(dir_, launch_file(sh_node("victim", idle(f("victim.pid")))));
    ASSERT_TRUE(launcher.wait_for_log("graph ready", 10.0)) << launcher.log();
    child = pid_in(f("victim.pid"));
    ASSERT_FALSE(gone(child));
    kill(launcher.pid(), SIGKILL);
    const int status = launcher.wait_exit(5.0);
    ASSERT_TRUE(WIFSIGNALED(status));
  }
  const bool child_gone = eventually(
      [&] {
        while (waitpid(-1, nullptr, WNOHANG) > 0) {
        }
        return gone(child);
      },
      2.0);
  EXPECT_TRUE(child_gone) << "pid " << child << " outlived the launcher";
  prctl(PR_SET_CHILD_SUBREAPER, 0);
  eventually([] { return waitpid(-1, nullptr, WNOHANG) < 0; }, 2.0);
}

// a node that says it waits (for observers) has that much more than --ready-timeout
TEST_F(Launch, AWaitingNodeHasItsWaitAddedToTheReadyTimeout) {
  const std::string waiter = "echo 'wait 3' >&$ENACT_READY_FD\nsleep 1.5\n" + std::string(kReady) + "\nwhile :; do sleep 0.05; done";
  const RunResult r = launch(sh_node("waiter", waiter), "--ready-timeout 0.5 --duration 0.5");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "graph ready")) << r.err;
  // the same node past its wait fails
  const std::string late = "echo 'wait 0.5' >&$ENACT_READY_FD\nsleep 2.5\n" + std::string(kReady) + "\nwhile :; do sleep 0.05; done";
  const RunResult l = launch(sh_node("late", late), "--ready-timeout 0.5 --duration 0.5");
  EXPECT_EQ(l.exit_code, 1) << l.err;
  EXPECT_TRUE(has(l.err, "did not report ready within 1 s")) << l.err;
}

// the registry holds the graph under its name while it runs, and never two of one name
TEST_F(Launch, TheGraphIsRegisteredByNameWhileItRunsAndNamesAreUnique) {
  setenv("ENACT_REGISTRY", f("registry").c_str(), 1);
  const std::string file = launch_file(sh_node("a", idle()));
  Launcher launcher(dir_, file);
  ASSERT_TRUE(launcher.wait_for_log("graph ready", 10.0)) << launcher.log();
  const RunResult list = run(std::string(ENACT_CLI) + " graph list");
  EXPECT_EQ(list.exit_code, 0) << list.err;
  EXPECT_TRUE(has(list.out, "launch ")) << "the default name: the file's stem\n" << list.out;
  EXPECT_TRUE(has(list.out, std::to_string(launcher.pid()))) << list.out;
  // the same name given again is refused; the default one is numbered
  const RunResult clash = launch(sh_node("b", idle()), "--name launch --duration 0.3");
  EXPECT_EQ(clash.exit_code, 1) << clash.err;
  EXPECT_TRUE(has(clash.err, "a graph named 'launch' runs already")) << clash.err;
  const RunResult numbered = run(std::string(ENACT_CLI) + " launch " + file + " --duration 0.3");
  EXPECT_EQ(numbered.exit_code, 0) << numbered.err;
  EXPECT_TRUE(has(numbered.err, "graph launch-2")) << numbered.err;
  kill(launcher.pid(), SIGTERM);
  ASSERT_NE(launcher.wait_exit(10.0), -1);
  EXPECT_TRUE(std::filesystem::is_empty(f("registry"))) << "every entry removed at the end";
  EXPECT_TRUE(has(run(std::string(ENACT_CLI) + " graph list").out, "no graph running"));
}

// kill -9 of a launcher leaves its entry and folder; the next look at the registry removes them
TEST_F(Launch, AKilledLaunchersEntryAndFolderAreCleanedByTheNext) {
  setenv("ENACT_REGISTRY", f("registry").c_str(), 1);
  std::string folder;
  {
    Launcher launcher(dir_, launch_file(sh_node("a", "echo $ENACT_GRAPH_DIR > " + f("dir") + "\n" + idle())));
    ASSERT_TRUE(launcher.wait_for_log("graph ready", 10.0)) << launcher.log();
    folder = lines_of(read_file(f("dir"))).at(0);
    ASSERT_TRUE(exists(folder));
    kill(launcher.pid(), SIGKILL);
    ASSERT_NE(launcher.wait_exit(5.0), -1);
  }
  EXPECT_TRUE(exists(folder)) << "nothing ran to remove it";
  EXPECT_FALSE(std::filesystem::is_empty(f("registry")));
  const RunResult list = run(std::string(ENACT_CLI) + " graph list");
  EXPECT_TRUE(has(list.out, "no graph running")) << list.out;
  EXPECT_FALSE(exists(folder));
  EXPECT_TRUE(std::filesystem::is_empty(f("registry")));
}

// a launcher killed by SIGKILL cannot stop its graph: each node gets SIGTERM from the kernel
// (its parent-death signal), so a driver stops cleanly (zero force, pins down)
TEST_F(Launch, KilledLauncherStopsItsChildrenCleanly) {
  const std::string trapper = "trap 'echo term > " + f("term") + "; exit 0' TERM\n" + kReady + "\nwhile :; do sleep 0.05; done";
  Launcher launcher(dir_, launch_file(sh_node("driver", trapper)));
  ASSERT_TRUE(launcher.wait_for_log("graph ready", 10.0)) << launcher.log();
  kill(launcher.pid(), SIGKILL);
  launcher.wait_exit(5.0);
  EXPECT_TRUE(eventually([&] { return exists(f("term")); }, 2.0)) << "the node never got SIGTERM";
}

TEST_F(Launch, SigintStopsTheGraphCleanly) {
  const std::string trapper = "trap 'echo term > " + f("term") + "; exit 0' TERM\n" + kReady + "\nwhile :; do sleep 0.05; done";
  Launcher launcher(dir_, launch_file(sh_node("a", idle(f("a.pid"))) + sh_node("b", trapper)));
  ASSERT_TRUE(launcher.wait_for_log("graph ready", 10.0)) << launcher.log();
  const pid_t a = pid_in(f("a.pid"));
  kill(launcher.pid(), SIGINT);
  const int status = launcher.wait_exit(10.0);
  ASSERT_TRUE(WIFEXITED(status)) << launcher.log();
  EXPECT_EQ(WEXITSTATUS(status), 0) << launcher.log();
  const std::string log = launcher.log();
  EXPECT_TRUE(has(log, "stopped a")) << log;
  EXPECT_TRUE(has(log, "stopped b")) << log;
  EXPECT_LT(at(log, "stopped b"), at(log, "stopped a")) << log;
  EXPECT_TRUE(exists(f("term")));
  EXPECT_TRUE(gone(a));
}

TEST_F(Launch, CheckPrintsThePlanAndStartsNothing) {
  const std::string nodes =
      "  - arg: {name: level, default: low}\n" +
      sh_node("maker", "touch " + f("made") + "\n" + kReady + "\nsleep 5", "param: [{name: level, value: $(var level)}]");
  const RunResult r = launch(nodes, "--check --arg level=high");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "arg   level = high")) << r.out;
  EXPECT_TRUE(has(r.out, "maker: /bin/sh -c")) << r.out;
  EXPECT_TRUE(has(r.out, "--name maker --param=level=high")) << r.out;
  EXPECT_FALSE(has(r.err, "started")) << r.err;
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(exists(f("made")));
}

TEST_F(Launch, BadFileStartsNothing) {
  const std::string nodes = sh_node("maker", "touch " + f("made") + "\n" + kReady + "\nsleep 5") +
                            "  - node:\n"
                            "      name: broken\n"
                            "      exec: /bin/sh\n"
                            "      colour: red\n";
  const RunResult r = launch(nodes, "--duration 1");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const int colour_line = static_cast<int>(lines_of(read_file(f("launch.yaml"))).size());
  EXPECT_TRUE(has(r.err, f("launch.yaml") + ":" + std::to_string(colour_line) + ":")) << r.err;
  EXPECT_TRUE(has(r.err, "colour")) << r.err;
  EXPECT_TRUE(has(r.err, "fix:")) << r.err;
  EXPECT_FALSE(has(r.err, "started")) << r.err;
  EXPECT_FALSE(exists(f("made")));
}

TEST_F(Launch, UndeclaredArgExitsOne) {
  const RunResult r = launch(sh_node("n", idle()), "--arg nope=1 --duration 0.1");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "nope")) << r.err;
}

TEST_F(Launch, ARealDeviceInSimulatedTimeIsRefusedAtItsLine) {
  // the Falcon and the Metec cells (here their emulators): people, who cannot be simulated
  const std::string file = std::string(ENACT_SOURCE_DIR) + "/launch/bridge_rt_usb_emulated.yaml";
  const RunResult r = run(std::string(ENACT_CLI) + " launch " + file + " --clock simulated --check");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, file + ":")) << r.err;
  EXPECT_TRUE(has(r.err, "device=falcon")) << r.err;
  EXPECT_TRUE(has(r.err, "device=metec")) << r.err;
  EXPECT_TRUE(has(r.err, "cannot be simulated")) << r.err;
  EXPECT_TRUE(has(r.err, "fix:")) << r.err;
  EXPECT_FALSE(has(r.out, "check: every node accepts")) << r.out;
}

TEST_F(Launch, BadOptionsExitTwo) {
  EXPECT_EQ(launch(sh_node("n", idle()), "--arg novalue").exit_code, 2);
  EXPECT_EQ(launch(sh_node("n", idle()), "--clock fast").exit_code, 2);
  EXPECT_EQ(launch(sh_node("n", idle()), "--ready-timeout 0").exit_code, 2);
  EXPECT_EQ(run(std::string(ENACT_CLI) + " launch").exit_code, 2);
}

}  // namespace
}  // namespace enact::test
