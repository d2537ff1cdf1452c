// Graphs as named sessions, end to end with the real `enact launch` and tools: two graphs on
// one machine (tools refuse to guess, --graph picks the right one), observers=N waiting for
// a late recorder that then has the first tick, a recorder started before its graph ending
// with it, the latched task/state for a late observer, a player registered as a graph.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "core/record/reader.h"
#include "msgs/param_update.pb.h"
#include "msgs/task_state.pb.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

constexpr const char* kRt = ENACT_SOURCE_DIR "/launch/bridge_rt.yaml";

// a command in the background, its output in files of `dir` named after `tag`
class Background {
 public:
  Background(const TempDir& dir, const std::string& tag, std::vector<std::string> argv)
      : out_(dir.file(tag + ".out")), err_(dir.file(tag + ".err")) {
    argv.insert(argv.begin(), ENACT_CLI);
    pid_ = spawn(argv, out_, err_);
  }
  ~Background() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;

  // its exit code (128 + signal), or -1 when it still runs after timeout_s
  int wait_exit(double timeout_s) {
    const auto end = after(timeout_s);
    int status = 0;
    while (pid_ > 0) {
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        break;
      }
      if (Clock::now() >= end) return -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return code_;
  }
  bool wait_err(const std::string& needle, double timeout_s) const {
    const auto end = after(timeout_s);
    while (Clock::now() < end) {
      if (err().find(needle) != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }
  std::string out() const { return read_file_or_empty(out_); }
  std::string err() const { return read_file_or_empty(err_); }

 private:
  std::string out_, err_;
  pid_t pid_ = -1;
  int code_ = -1;
};

class Sessions : public ::testing::Test {
 protected:
  // a registry of this test's own: the graphs of other tests never count
  void SetUp() override { setenv("ENACT_REGISTRY", dir_.file("registry").c_str(), 1); }

  RunResult enact(const std::string& args) const { return run(std::string(ENACT_CLI) + " " + args); }
  // the attach endpoint of running graph `name`, from `enact graph list` ("" : not listed)
  std::string endpoint_of(const std::string& name) const {
    std::smatch m;
    const std::string list = enact("graph list").out;
    if (!std::regex_search(list, m, std::regex("(^|\\n)" + name + " +(\\S+)"))) return "";
    return m[2].str();
  }
  bool wait_listed(const std::string& name, double timeout_s) const {
    const auto end = after(timeout_s);
    while (Clock::now() < end) {
      if (!endpoint_of(name).empty()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }

  TempDir dir_;
};

TEST_F(Sessions, WithTwoGraphsToolsRefuseToGuessAndGraphPicksTheRightOne) {
  Background a(dir_, "a", {"launch", kRt, "--name", "left", "--duration", "30"});
  Background b(dir_, "b", {"launch", kRt, "--name", "right", "--duration", "30"});
  ASSERT_TRUE(a.wait_err("graph left ready", 30.0)) << a.err();
  ASSERT_TRUE(b.wait_err("graph right ready", 30.0)) << b.err();
  const std::string left = endpoint_of("left"), right = endpoint_of("right");
  ASSERT_FALSE(left.empty());
  ASSERT_FALSE(right.empty());
  ASSERT_NE(left, right);
  // no name: no guess, both listed, exit 2
  for (const std::string& tool : std::vector<std::string>{"topic list --wait 1", "param set sim.stiffness_n_per_m 600 --wait 1", "record -o " + dir_.file("x.mcap") + " --wait 1"}) {
    const RunResult r = enact(tool);
    EXPECT_EQ(r.exit_code, 2) << tool << "\n" << r.err;
    EXPECT_NE(r.err.find("several graphs run"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("left"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("right"), std::string::npos) << r.err;
  }
  // --graph right: the change reaches right's simulator only (its ack on right's attach point)
  Observer on_left(left), on_right(right);
  bus::Subscriber<msgs::ParamAck> left_acks(on_left.bytes(), "param/ack"), right_acks(on_right.bytes(), "param/ack");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const RunResult set = enact("param set sim.stiffness_n_per_m 600 --graph right");
  ASSERT_EQ(set.exit_code, 0) << set.out << set.err;
  EXPECT_NE(set.out.find("applied"), std::string::npos) << set.out;
  EXPECT_NE(set.err.find("attached to graph right at " + right), std::string::npos) << set.err;
  msgs::ParamAck ack;
  EXPECT_TRUE(right_acks.receive(ack, 2000));
  EXPECT_TRUE(ack.applied());
  EXPECT_FALSE(left_acks.receive(ack, 500)) << "left's simulator got a change meant for right";
  // the topic tools say where they attached
  const RunResult list = enact("topic list --graph left");
  EXPECT_EQ(list.exit_code, 0) << list.err;
  EXPECT_NE(list.err.find("attached to graph left at " + left), std::string::npos) << list.err;
}

// two graphs of one launch file, no --name: the registry numbers the second, and each
// announces on graph/topics the name `enact graph list` shows
TEST_F(Sessions, TwoGraphsOfOneLaunchFileAnnounceTheirRegistryNames) {
  Background a(dir_, "a", {"launch", kRt, "--duration", "30"});
  ASSERT_TRUE(a.wait_err("graph bridge_rt ready", 30.0)) << a.err();
  Background b(dir_, "b", {"launch", kRt, "--duration", "30"});
  ASSERT_TRUE(b.wait_err("graph bridge_rt-2 ready", 30.0)) << b.err();
  for (const std::string name : {"bridge_rt", "bridge_rt-2"}) {
    const std::string endpoint = endpoint_of(name);
    ASSERT_FALSE(endpoint.empty()) << name << " not in enact graph list";
    const RunResult list = enact("topic list --graph " + name);
    ASSERT_EQ(list.exit_code, 0) << list.err;
    EXPECT_NE(list.out.find("graph " + name + " at " + endpoint + "\n"), std::string::npos) << list.out;
  }
}

TEST_F(Sessions, ObserversWaitKeepsTheGraphForALateRecorderThatGetsTheFirstTick) {
  Background launch(dir_, "launch", {"launch", kRt, "--name", "waits", "--duration", "2", "--arg", "observers=1"});
  // the endpoint is known before the wait, and the node says it waits
  ASSERT_TRUE(launch.wait_err("graph waits: observers attach at", 20.0)) << launch.err();
  ASSERT_TRUE(launch.wait_err("waiting up to 60 s for 1 observer", 20.0)) << launch.err();
  // longer than the launcher's ready timeout (10 s): it must not give up
  std::this_thread::sleep_for(std::chrono::seconds(12));
  ASSERT_EQ(launch.wait_exit(0.0), -1) << "the launcher gave up waiting:\n" << launch.err();
  const std::string file = dir_.file("late.mcap");
  const RunResult rec = enact("record --graph waits -o " + file);
  EXPECT_EQ(rec.exit_code, 0) << rec.err;
  EXPECT_EQ(launch.wait_exit(20.0), 0) << launch.err();
  EXPECT_EQ(launch.err().find("running anyway"), std::string::npos) << launch.err();
  record::Reader r(file);
  ASSERT_TRUE(r.complete());
  std::uint64_t first = 0;
  r.for_each([&](const record::Message& m) {
    if (m.topic != "ffd/state") return true;
    first = m.sequence;
    return false;
  });
  EXPECT_EQ(first, 1u) << "the recording starts at the first tick";
}

TEST_F(Sessions, RecorderStartedBeforeItsGraphWaitsAndEndsWithIt) {
  const std::string file = dir_.file("follow.mcap");
  Background rec(dir_, "rec", {"record", "--graph", "soon", "-o", file});
  ASSERT_TRUE(rec.wait_err("waiting for graph 'soon'", 10.0)) << rec.err();
  Background launch(dir_, "launch", {"launch", kRt, "--name", "soon", "--duration", "3"});
  ASSERT_EQ(launch.wait_exit(60.0), 0) << launch.err();
  // ends by itself, within a few seconds, the file closed
  EXPECT_EQ(rec.wait_exit(5.0), 0) << rec.err();
  EXPECT_NE(rec.err().find("graph soon ended"), std::string::npos) << rec.err();
  record::Reader r(file);
  EXPECT_TRUE(r.complete());
  EXPECT_TRUE(r.damage().empty());
  // enact play: a graph of its own, found by name, and gone at its end
  Background play(dir_, "play", {"play", file});
  ASSERT_TRUE(wait_listed("play:follow.mcap", 20.0)) << play.err();
  const RunResult topics = enact("topic list --graph play:follow.mcap");
  EXPECT_EQ(topics.exit_code, 0) << topics.err;
  EXPECT_NE(topics.out.find("ffd/state"), std::string::npos) << topics.out;
  EXPECT_EQ(play.wait_exit(30.0), 0) << play.err();
  EXPECT_TRUE(endpoint_of("play:follow.mcap").empty());
  EXPECT_TRUE(std::filesystem::is_empty(dir_.file("registry")));
}

TEST_F(Sessions, ALateObserverSeesTheTrialsStateAtOnce) {
  Background launch(dir_, "launch", {"launch", kRt, "--name", "state", "--duration", "60"});
  ASSERT_TRUE(launch.wait_err("graph state ready", 30.0)) << launch.err();
  // the scripted hand completes the bridge (after a fall) in about 10 s
  Observer watch(endpoint_of("state"));
  bus::Subscriber<msgs::TaskState> states(watch.bytes(), "task/state");
  msgs::TaskState s;
  const auto end = after(50.0);
  while (Clock::now() < end && !(states.receive(s, 100) && s.phase() == msgs::TaskState::COMPLETED)) {
  }
  ASSERT_EQ(s.phase(), msgs::TaskState::COMPLETED);
  // long after the change: a new observer gets the state at once
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const auto asked = Clock::now();
  const RunResult echo = enact("topic echo task/state --once --graph state");
  EXPECT_LT(seconds_since(asked), 5.0);
  ASSERT_EQ(echo.exit_code, 0) << echo.err;
  EXPECT_NE(echo.out.find("phase: COMPLETED"), std::string::npos) << echo.out;
  // proto3 text leaves zero values out
  const std::string falls = s.falls() == 0 ? "" : "falls: " + std::to_string(s.falls());
  if (!falls.empty()) EXPECT_NE(echo.out.find(falls), std::string::npos) << echo.out;
  EXPECT_EQ(echo.out.find("falls:") != std::string::npos, !falls.empty()) << echo.out;
}

}  // namespace
}  // namespace enact::test
