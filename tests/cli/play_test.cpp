// enact play as a user runs it: on a terminal (a pseudo-terminal driving the real binary)
// Space pauses, s steps one message, the progress gives the total, and the terminal's mode
// comes back after Ctrl-C; off a terminal --delay holds the first message and the progress
// comes as plain lines.
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>

#include <regex>

#include "core/bus/attach.h"
#include "core/record/writer.h"
#include "msgs/device_state.pb.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

constexpr std::int64_t kStart_ns = 1'000'000'000'000;
constexpr std::int64_t kPeriod_ns = 10'000'000;  // one message every 10 ms

// a recording of ffd/state over `seconds`: header.seq k logged at k x 10 ms
std::string make_recording(const TempDir& dir, int seconds) {
  const std::string path = dir.file("states.mcap");
  record::Writer w(path);
  const std::uint16_t schema = w.add_schema("enact.msgs.DeviceState", "protobuf", "");
  const std::uint16_t channel = w.add_channel(schema, "ffd/state", "protobuf", {{"publisher", "ffd"}});
  for (int k = 0; k <= seconds * 100; ++k) {
    msgs::DeviceState s;
    s.mutable_header()->set_seq(static_cast<std::uint64_t>(k));
    w.write(channel, static_cast<std::uint32_t>(k), kStart_ns + k * kPeriod_ns, 0, s.SerializeAsString());
  }
  w.close();
  return path;
}

// the play's ffd/state as an observer receives it, through the attach point
class Observer {
 public:
  explicit Observer(const std::string& endpoint) {
    bus::attach_connect(sub_.socket(), endpoint, {});
    sub_.subscribe("ffd/state");
  }
  // what arrives within `seconds`: counted, the last seq kept, the first's arrival noted
  void take(double seconds) {
    const auto end = after(seconds);
    bus::RawMessage raw;
    msgs::DeviceState s;
    while (Clock::now() < end) {
      if (!sub_.receive(raw, 20) || raw.topic() != "ffd/state" || !s.ParseFromArray(raw.payload(), static_cast<int>(raw.payload_size()))) continue;
      if (count == 0) first_arrival = Clock::now(), first_seq = s.header().seq();
      ++count;
      last_seq = s.header().seq();
    }
  }
  int count = 0;
  std::uint64_t first_seq = 0, last_seq = 0;
  Clock::time_point first_arrival;

 private:
  bus::ByteSubscriber sub_;
};

// `enact play ARGS` on a pseudo-terminal, its own registry in `dir`
class PlayOnTerminal {
 public:
  PlayOnTerminal(const TempDir& dir, std::vector<std::string> args) {
    args.insert(args.begin(), {ENACT_CLI, "play"});
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string registry = dir.file("registry");
    pid_ = forkpty(&master_, nullptr, nullptr, nullptr);
    if (pid_ == 0) {
      setenv("ENACT_REGISTRY", registry.c_str(), 1);
      execv(argv[0], argv.data());
      _exit(127);
    }
  }
  ~PlayOnTerminal() {
    if (pid_ > 0 && !exited_) kill(pid_, SIGKILL), waitpid(pid_, nullptr, 0);
    if (master_ >= 0) close(master_);
  }
  // what the terminal shows, read for up to `seconds` or until `pattern` appears
  bool read_until(const std::regex& pattern, double seconds) {
    const auto end = after(seconds);
    while (!std::regex_search(screen, pattern)) {
      if (Clock::now() > end) return false;
      pump(20);
    }
    return true;
  }
  void pump(int timeout_ms) {
    pollfd p{master_, POLLIN, 0};
    char buf[4096];
    if (poll(&p, 1, timeout_ms) == 1) {
      const ssize_t n = read(master_, buf, sizeof buf);
      if (n > 0) screen.append(buf, static_cast<std::size_t>(n));
    }
  }
  void type(char key) { ASSERT_EQ(write(master_, &key, 1), 1); }
  // the terminal's local modes (the pseudo-terminal's two ends share them)
  tcflag_t local_modes() const {
    termios t{};
    tcgetattr(master_, &t);
    return t.c_lflag;
  }
  // SIGINT (Ctrl-C), then its exit status (-1: still running after 10 s)
  int interrupt() {
    kill(pid_, SIGINT);
    int status = 0;
    const auto end = after(10.0);
    while (waitpid(pid_, &status, WNOHANG) == 0) {
      if (Clock::now() > end) return -1;
      pump(20);
    }
    exited_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string screen;

 private:
  pid_t pid_ = -1;
  int master_ = -1;
  bool exited_ = false;
};

const std::regex kAttachLine("observers attach at (tcp://\\S+)");

std::string endpoint_in(const std::string& text) {
  std::smatch m;
  return std::regex_search(text, m, kAttachLine) ? m[1].str() : "";
}

TEST(PlayKeys, SpacePausesAndSStepsOneMessage) {
  const TempDir dir;
  PlayOnTerminal play(dir, {make_recording(dir, 60), "--delay", "1"});
  ASSERT_TRUE(play.read_until(kAttachLine, 20.0)) << play.screen;
  Observer observer(endpoint_in(play.screen));
  // playing: messages flow, the terminal is in raw mode, the progress names the total
  ASSERT_TRUE(eventually([&] { observer.take(0.1); return observer.count > 20; }, 20.0));
  EXPECT_EQ(play.local_modes() & (ICANON | ECHO), 0u);
  ASSERT_TRUE(play.read_until(std::regex(" / 60\\.0 s"), 5.0)) << play.screen;

  // Space: the stream stops (what was on its way arrives within the first 0.5 s)
  play.type(' ');
  ASSERT_TRUE(play.read_until(std::regex("paused"), 5.0)) << play.screen;
  observer.take(0.5);
  const int paused_at = observer.count;
  const std::uint64_t paused_seq = observer.last_seq;
  observer.take(1.5);
  EXPECT_EQ(observer.count, paused_at) << "messages kept coming while paused";

  // s: exactly one message, the next one
  play.type('s');
  observer.take(1.5);
  EXPECT_EQ(observer.count, paused_at + 1);
  EXPECT_EQ(observer.last_seq, paused_seq + 1);

  // Space again: it plays on
  play.type(' ');
  ASSERT_TRUE(eventually([&] { observer.take(0.1); return observer.count > paused_at + 20; }, 10.0));

  // Ctrl-C: a clean exit, the terminal's mode restored
  EXPECT_EQ(play.interrupt(), 0) << play.screen;
  EXPECT_EQ(play.local_modes() & (ICANON | ECHO), static_cast<tcflag_t>(ICANON | ECHO));
}

TEST(PlayKeys, DelayHoldsTheFirstMessageAndProgressComesAsLines) {
  const TempDir dir;
  const std::string out = dir.file("play.out"), err = dir.file("play.err");
  const auto started = Clock::now();
  const pid_t pid = spawn({ENACT_CLI, "play", make_recording(dir, 6), "--delay", "3"}, out, err, {"ENACT_REGISTRY=" + dir.file("registry")});
  ASSERT_TRUE(eventually([&] { return !endpoint_in(read_file_or_empty(err)).empty(); }, 20.0)) << read_file_or_empty(err);
  Observer observer(endpoint_in(read_file_or_empty(err)));
  observer.take(12.0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  EXPECT_EQ(WEXITSTATUS(status), 0);

  // the first message went out no sooner than 3 s after the start, on its recorded time
  ASSERT_GT(observer.count, 0);
  const double sent_at_s = std::chrono::duration<double>(observer.first_arrival - started).count() - static_cast<double>(observer.first_seq) * 0.01;
  EXPECT_GE(sent_at_s, 3.0);
  EXPECT_LT(sent_at_s, 13.0);

  // off a terminal: whole lines with the total, no carriage returns, no key hints
  const std::string log = read_file(err);
  const std::regex line("enact play: [0-9.]+ / 6\\.0 s, [0-9]+ messages\n");
  EXPECT_GE(std::distance(std::sregex_iterator(log.begin(), log.end(), line), std::sregex_iterator()), 2) << log;
  EXPECT_EQ(log.find('\r'), std::string::npos) << log;
  EXPECT_EQ(log.find("Space"), std::string::npos) << log;
}

// as a node of a graph no one listens to (its graph folder, no attach point), play says it
// waits (and how long), then that it plays anyway; standalone, its own attach point listens
TEST(PlayKeys, TheWaitForSubscribersIsSaid) {
  const TempDir dir;
  const std::string file = make_recording(dir, 1);
  const RunResult alone = run("ENACT_GRAPH_DIR=" + dir.path() + " " + std::string(ENACT_CLI) + " play " + file + " --wait 1 --rate 0");
  EXPECT_EQ(alone.exit_code, 0) << alone.err;
  EXPECT_NE(alone.err.find("enact play: waiting up to 1 s for a subscriber of every topic played (--wait S)\n"), std::string::npos) << alone.err;
  EXPECT_NE(alone.err.find("playing anyway"), std::string::npos) << alone.err;

  const std::string out = dir.file("play.out"), err = dir.file("play.err");
  const pid_t pid = spawn({ENACT_CLI, "play", file, "--wait", "20"}, out, err, {"ENACT_REGISTRY=" + dir.file("registry")});
  ASSERT_TRUE(eventually([&] { return !endpoint_in(read_file_or_empty(err)).empty(); }, 20.0)) << read_file_or_empty(err);
  Observer observer(endpoint_in(read_file_or_empty(err)));
  observer.take(4.0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(read_file(err).find("waiting up to"), std::string::npos) << read_file(err);
}

TEST(PlayKeys, TopicsTakeASlashAndMisspellingsGetTheClosest) {
  const TempDir dir;
  const std::string file = make_recording(dir, 1);
  EXPECT_EQ(run(std::string(ENACT_CLI) + " play " + file + " --topics /ffd/state --remap /ffd/state:=/replayed --check").exit_code, 0);
  const RunResult wrong = run(std::string(ENACT_CLI) + " play " + file + " --topics ffd/stat --check");
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("no topic 'ffd/stat' in " + file + " (did you mean ffd/state?) (topics: ffd/state)"), std::string::npos) << wrong.err;
}

}  // namespace
}  // namespace enact::test
