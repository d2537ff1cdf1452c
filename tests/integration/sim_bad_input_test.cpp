// Integration: enact-sim run alone (no launcher) against a fake FFD driver played by this
// test: garbage on ffd/state is counted and ignored, every valid DeviceState is answered.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/bus/endpoints.h"
#include "core/bus/typed.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

// enact-sim --name sim --param scene=... --param ffd_node=fake, with ENACT_GRAPH_DIR=dir,
// stderr into dir/sim.err
class SimProcess {
 public:
  SimProcess(const TempDir& dir, const std::string& graph_dir) : err_(dir.file("sim.err")) {
    const std::string scene = "scene=" + source_path("launch/scenes/bridge.yaml");
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      setenv("ENACT_GRAPH_DIR", graph_dir.c_str(), 1);
      unsetenv("ENACT_READY_FD");
      const int err = open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (err >= 0) dup2(err, 2);
      execl(ENACT_SIM, ENACT_SIM, "--name", "sim", "--param", scene.c_str(), "--param", "ffd_node=fake", static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~SimProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  SimProcess(const SimProcess&) = delete;
  SimProcess& operator=(const SimProcess&) = delete;

  bool running() {
    if (pid_ <= 0) return false;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) != pid_) return true;
    pid_ = -1;
    return false;
  }

  // SIGTERM, up to timeout_s: the exit code, 128 + signal, or -1 (still running: killed)
  int stop(double timeout_s) {
    if (pid_ <= 0) return -1;
    kill(pid_, SIGTERM);
    const auto end = after(timeout_s);
    int status = 0;
    while (Clock::now() < end) {
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
  }

  std::string log() const {
    try {
      return read_file(err_);
    } catch (const std::exception&) {
      return "";
    }
  }

 private:
  std::string err_;
  pid_t pid_ = -1;
};

TEST(IntegrationSim, GarbageOnFfdStateIsCountedAndIgnored) {
  const auto t0 = Clock::now();
  TempDir dir;
  TempDir graph_dir;  // the sockets: ipc://<graph_dir>/fake.pub (this test), .../sim.pub
  SimProcess sim(dir, graph_dir.path());

  // the fake FFD driver, and a subscriber to the simulator's answers and status
  bus::BytePublisher fake(bus::ipc_endpoint(graph_dir.path(), "fake"), {.node = "fake", .send_hwm = 1000});
  bus::Publisher<msgs::DeviceState> states(fake, "ffd/state");
  bus::ByteSubscriber in;
  in.set_receive_hwm(100000);
  bus::Subscriber<msgs::ForceCommand> forces(in, "ffd/force");
  bus::Subscriber<msgs::NodeStatus> statuses(in, "node/status");
  in.connect(bus::ipc_endpoint(graph_dir.path(), "sim"));

  // valid samples: on the top of the bridge, at the start of its centerline, pressed in 0.5 mm
  msgs::DeviceState state;
  state.mutable_position()->set_x(-0.0074246);
  state.mutable_position()->set_y(-0.0222739);
  state.mutable_position()->set_z(0.0115);
  auto send_valid = [&] {
    state.mutable_header()->set_stamp_ns(0);
    states.publish(state);
    return state.header().seq();
  };
  std::set<std::uint64_t> answered;
  std::vector<msgs::NodeStatus> status_seen;
  std::uint64_t pushing_up = 0;
  auto drain = [&](int timeout_ms) {
    bus::RawMessage raw;
    msgs::ForceCommand command;
    msgs::NodeStatus status;
    while (in.receive(raw, timeout_ms)) {
      timeout_ms = 0;
      if (forces.accept(raw, command)) {
        answered.insert(command.answered_seq());
        pushing_up += command.force().z() > 0.0;
      } else if (statuses.accept(raw, status)) {
        status_seen.push_back(status);
      }
    }
  };

  // wait until the simulator listens to us and we hear it: send until an answer comes back
  const auto sync_end = after(15.0);
  while (answered.empty() && Clock::now() < sync_end && sim.running()) {
    send_valid();
    drain(20);
  }
  drain(50);  // the answers to the other sync samples
  ASSERT_FALSE(answered.empty()) << "no ffd/force from enact-sim within 15 s\n" << sim.log();

  // garbage, interleaved with valid samples; every valid one must be answered
  const std::string device_state = msgs::DeviceState::descriptor()->full_name();
  const std::string force_command = msgs::ForceCommand::descriptor()->full_name();
  std::mt19937 random(12345);
  std::string noise(40, '\0');
  for (char& c : noise) c = static_cast<char>(random() & 0xff);
  noise[0] = '\x0f';  // field 1, wire type 7: no such wire type, so it cannot parse
  ASSERT_FALSE(msgs::DeviceState().ParseFromString(noise));
  msgs::DeviceState valid_payload = state;
  valid_payload.mutable_header()->set_seq(999999);  // a seq the fake never reaches
  const std::string valid_bytes = valid_payload.SerializeAsString();
  zmq::socket_t& raw = fake.socket();
  std::vector<std::uint64_t> sent;
  constexpr int kRounds = 3;
  for (int round = 0; round < kRounds; ++round) {
    sent.push_back(send_valid());
    // 1. one frame: malformed at the byte layer (wrong frame count)
    ASSERT_TRUE(raw.send(zmq::buffer(std::string_view("ffd/state")), zmq::send_flags::dontwait));
    sent.push_back(send_valid());
    // 2. three frames, the type of another message: malformed at the typed layer
    const std::string force_bytes = msgs::ForceCommand().SerializeAsString();
    ASSERT_TRUE(fake.send("ffd/state", force_command, force_bytes.data(), force_bytes.size()));
    sent.push_back(send_valid());
    // 3. the right type, a payload that does not parse: malformed at the typed layer
    ASSERT_TRUE(fake.send("ffd/state", device_state, noise.data(), noise.size()));
    sent.push_back(send_valid());
    // 4. four frames: malformed at the byte layer (the extra frame is read and dropped)
    ASSERT_TRUE(raw.send(zmq::buffer(std::string_view("ffd/state")), zmq::send_flags::sndmore | zmq::send_flags::dontwait));
    ASSERT_TRUE(raw.send(zmq::buffer(device_state), zmq::send_flags::sndmore | zmq::send_flags::dontwait));
    ASSERT_TRUE(raw.send(zmq::buffer(valid_bytes), zmq::send_flags::sndmore | zmq::send_flags::dontwait));
    ASSERT_TRUE(raw.send(zmq::buffer(std::string_view("extra")), zmq::send_flags::dontwait));
    sent.push_back(send_valid());
    // 5. a topic that only shares a prefix with ffd/state: skipped silently, not answered
    ASSERT_TRUE(fake.send("ffd/state2", device_state, valid_bytes.data(), valid_bytes.size()));
    sent.push_back(send_valid());
    drain(5);
  }
  constexpr std::uint64_t kMalformed = 4 * kRounds;

  // keep the simulator fed (its node/status goes out once a second, on a sample) until a
  // status counts all the garbage, at most 5 s
  const auto status_end = after(5.0);
  std::uint64_t malformed = 0;
  while (Clock::now() < status_end && malformed < kMalformed && sim.running()) {
    sent.push_back(send_valid());
    drain(1);
    std::this_thread::sleep_for(std::chrono::microseconds(500));  // ~1 kHz: no need to flood
    for (const auto& s : status_seen) {
      for (const auto& t : s.topics()) {
        if (t.topic() == "ffd/state") malformed = std::max<std::uint64_t>(malformed, t.malformed());
      }
    }
  }
  drain(200);
  EXPECT_TRUE(sim.running()) << sim.log();

  std::size_t missing = 0;
  for (std::uint64_t seq : sent) missing += !answered.contains(seq);
  EXPECT_EQ(missing, 0u) << "of " << sent.size() << " valid samples sent after the first answer, " << missing << " got no ffd/force";
  EXPECT_FALSE(answered.contains(999999)) << "a message on ffd/state2 was taken for ffd/state";
  EXPECT_GT(pushing_up, 0u) << "pressed into the top of the bridge, the simulator never pushed up";
  EXPECT_EQ(forces.counters().malformed, 0u);
  EXPECT_EQ(statuses.counters().malformed, 0u);
  ASSERT_FALSE(status_seen.empty()) << "no node/status from enact-sim\n" << sim.log();
  // 1-frame and 4-frame messages are counted by the byte layer (bytes.h: "a wrong number of
  // frames counts as malformed"), wrong type and bad payload by the typed layer: all of them
  // land in the same per-topic counter, reported in node/status
  EXPECT_GE(malformed, 2u);
  EXPECT_EQ(malformed, kMalformed) << "ffd/state malformed in enact-sim's node/status: " << status_seen.back().ShortDebugString();
  const msgs::NodeStatus& last = status_seen.back();
  EXPECT_EQ(last.node(), "sim");

  EXPECT_EQ(sim.stop(5.0), 0) << sim.log();
  std::printf("[ timing ] %.1f s; %zu valid samples answered, %llu malformed counted\n", seconds_since(t0), sent.size(),
              static_cast<unsigned long long>(malformed));
}

}  // namespace
}  // namespace enact::test
