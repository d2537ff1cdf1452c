// Remote access end to end, on 127.0.0.1: the real co-located graph (launch/bridge_rt.yaml)
// started by the real `enact launch --access`, keys made by `enact keys new`, clients from the
// command line, this process and Python. Only keyed clients see anything, only operators change
// anything, every applied change is recorded with its key's name, and a flood of param/set
// from an operator does not slow the loop.
//
// Machine assumptions: 2 noisy shared cores; rates are checked with generous bounds only.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/bus/attach.h"
#include "core/bus/client.h"
#include "core/record/reader.h"
#include "msgs/param_update.pb.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

constexpr double kGraphDuration_s = 40.0;  // a safety net: every test stops its graph itself
constexpr double kLoopRate_hz = 5000.0;    // bridge_rt.yaml's default rate

// a graph launched with an access file: key "alice" operates, "bob" observes, "eve" has a
// key the file does not list
class Access : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : {"graph", "alice", "bob", "eve"}) {
      const RunResult r = run(kCli + " keys new " + name + " --dir " + dir_.path());
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    write_file(dir_.file("access.yaml"),
               "server_key: graph.key\n"
               "clients:\n"
               "  - {name: alice, public_key_file: alice.pub, role: operate}\n"
               "  - {name: bob, public_key_file: bob.pub, role: observe}\n");
    launcher_ = std::make_unique<Launcher>(dir_, source_path("launch/bridge_rt.yaml"), kGraphDuration_s, std::vector<std::string>{}, "",
                                           std::vector<std::string>{"--access", dir_.file("access.yaml")});
    ASSERT_TRUE(launcher_->wait_log("observers attach at", kReadyTimeout_s)) << launcher_->log();
  }

  // `--attach E --key WHO.key --server-key SERVER` for the command line
  std::string keys(const std::string& who, const std::string& server = "graph.pub") const {
    return " --attach " + launcher_->endpoint() + " --key " + dir_.file(who + ".key") + " --server-key " + dir_.file(server);
  }
  bus::ClientKeys client(const std::string& who) const { return bus::client_keys(dir_.file(who + ".key"), dir_.file("graph.pub")); }

  TempDir dir_;
  std::unique_ptr<Launcher> launcher_;
};

// ffd/state as an observer saw it: every message, and the loop's own rate (by its stamps)
struct StateRate {
  std::uint64_t received = 0, lost = 0, span = 0;
  double loop_hz = 0.0;
};
StateRate rate_of(const std::vector<msgs::DeviceState>& states) {
  StateRate r;
  if (states.size() < 2) return r;
  r.span = states.back().header().seq() - states.front().header().seq() + 1;
  r.received = states.size();
  r.lost = r.span - r.received;
  r.loop_hz = static_cast<double>(r.span - 1) * 1e9 / static_cast<double>(states.back().header().stamp_ns() - states.front().header().stamp_ns());
  return r;
}

TEST_F(Access, OnlyKeyedClientsSeeTheGraphAndAWrongServerKeyIsSaid) {
  // a client without keys: nothing at all in 3 s
  bus::ByteSubscriber nobody;
  nobody.subscribe("graph/topics");
  nobody.subscribe("ffd/state");
  nobody.connect(launcher_->endpoint());
  EXPECT_FALSE(nobody.receive(3000).has_value());
  // the command line says why
  const RunResult plain = run(kCli + " topic list --attach " + launcher_->endpoint());
  EXPECT_EQ(plain.exit_code, 1);
  EXPECT_NE(plain.err.find("requires keys"), std::string::npos) << plain.err;
  // a key the access file does not list: refused, and the graph logs its fingerprint
  const RunResult eve = run(kCli + " topic list" + keys("eve"));
  EXPECT_EQ(eve.exit_code, 1);
  EXPECT_NE(eve.err.find("refused this key"), std::string::npos) << eve.err;
  const std::string eve_key = run(kCli + " keys show " + dir_.file("eve.pub")).out;
  EXPECT_TRUE(launcher_->wait_log("refused a client key " + eve_key.substr(0, 8), 5.0)) << launcher_->log();
  // bob's key with the wrong server key: the handshake fails, and says what to check
  const RunResult wrong = run(kCli + " topic list" + keys("bob", "alice.pub"));
  EXPECT_EQ(wrong.exit_code, 1);
  EXPECT_NE(wrong.err.find("--server-key is not this graph's public key"), std::string::npos) << wrong.err;
  // bob's right keys: the graph's topics
  const RunResult bob = run(kCli + " topic list" + keys("bob"));
  EXPECT_EQ(bob.exit_code, 0) << bob.err;
  EXPECT_NE(bob.out.find("ffd/state"), std::string::npos) << bob.out;
}

TEST_F(Access, AnObserverReceivesStatesAtRateAndIsRefusedParamSet) {
  Observer obs(launcher_->endpoint(), client("bob"));
  obs.states.emplace(obs.bytes(), "ffd/state");
  Observed seen;
  obs.observe(3.0, seen);
  const StateRate r = rate_of(seen.states);
  std::printf("[ observer ] ffd/state: %llu received, %llu lost, loop at %.0f Hz by its stamps\n", static_cast<unsigned long long>(r.received),
              static_cast<unsigned long long>(r.lost), r.loop_hz);
  // every state the loop published, over encrypted connections (the loop's own pace on this
  // busy machine is not the point here: the flood test compares it)
  ASSERT_GT(r.received, 1000u);
  EXPECT_LT(r.lost * 100, r.span) << "more than 1 % of ffd/state lost by the keyed observer";
  // bob's parameter change is refused by the graph, with the reason
  const RunResult set = run(kCli + " param set sim.stiffness_n_per_m 3000" + keys("bob"));
  EXPECT_EQ(set.exit_code, 1) << set.out << set.err;
  EXPECT_NE(set.out.find("refused"), std::string::npos) << set.out;
  EXPECT_NE(set.out.find("role observe"), std::string::npos) << set.out;
  // the same through enact topic pub: refused for bob, applied for alice (an operator)
  const std::string pub = kCli + " topic pub param/set '{name: sim.stiffness_n_per_m, number: 3000}'";
  const RunResult observer_pub = run(pub + keys("bob"));
  EXPECT_EQ(observer_pub.exit_code, 1) << observer_pub.out << observer_pub.err;
  EXPECT_NE(observer_pub.out.find("refused"), std::string::npos) << observer_pub.out;
  EXPECT_NE(observer_pub.out.find("role observe"), std::string::npos) << observer_pub.out;
  const RunResult operator_pub = run(pub + keys("alice"));
  EXPECT_EQ(operator_pub.exit_code, 0) << operator_pub.out << operator_pub.err;
  EXPECT_NE(operator_pub.out.find("sim.stiffness_n_per_m: applied"), std::string::npos) << operator_pub.out;
}

TEST_F(Access, AnOperatorsChangeIsAppliedAndRecordedWithItsKeyName) {
  // bob records (an observer may), alice changes the stiffness
  const std::string mcap = dir_.file("audit.mcap");
  const pid_t recorder = spawn({kCli, "record", "-o", mcap, "--duration", "6", "--attach", launcher_->endpoint(), "--key", dir_.file("bob.key"), "--server-key",
                                dir_.file("graph.pub")},
                               dir_.file("record.out"), dir_.file("record.err"));
  const auto attached = after(10.0);
  const auto recorder_log = [&] {
    try {
      return read_file(dir_.file("record.err"));
    } catch (const std::exception&) {
      return std::string();
    }
  };
  while (recorder_log().find("attached") == std::string::npos && Clock::now() < attached) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const RunResult set = run(kCli + " param set sim.stiffness_n_per_m 3000" + keys("alice"));
  EXPECT_EQ(set.exit_code, 0) << set.out << set.err;
  EXPECT_NE(set.out.find("applied"), std::string::npos) << set.out;
  int status = 0;
  waitpid(recorder, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << recorder_log();
  // the recording holds the change with alice's key name, and its ack, applied
  record::Reader reader(mcap);
  std::vector<msgs::ParamUpdate> updates;
  std::vector<msgs::ParamAck> acks;
  reader.for_each([&](const record::Message& m) {
    if (m.topic == "param/set") updates.emplace_back().ParseFromArray(m.data.data(), static_cast<int>(m.data.size()));
    if (m.topic == "param/ack") acks.emplace_back().ParseFromArray(m.data.data(), static_cast<int>(m.data.size()));
    return true;
  });
  ASSERT_FALSE(updates.empty()) << "no param/set in the recording";
  for (const auto& u : updates) {
    EXPECT_EQ(u.header().sender_key(), "alice") << u.ShortDebugString();
    EXPECT_EQ(u.number(), 3000.0);
  }
  bool applied = false;
  for (const auto& a : acks) applied = applied || (a.request_id() == updates.front().request_id() && a.applied());
  EXPECT_TRUE(applied) << "no applied param/ack for alice's request in the recording";
}

TEST_F(Access, ThePythonExampleAttachesWithKeys) {
  const std::string python = "/usr/bin/python3";
  if (run(python + " -c 'import zmq, google.protobuf'").exit_code != 0) GTEST_SKIP() << "python3-zmq or python3-protobuf not installed";
  const std::string script = python + " " + source_path("scripts/attach_example.py") + " " + launcher_->endpoint() + " ffd/state --count 2";
  const RunResult keyed = run(script + " --timeout 10 --key " + dir_.file("bob.key") + " --server-key " + dir_.file("graph.pub"));
  EXPECT_EQ(keyed.exit_code, 0) << keyed.out << keyed.err;
  EXPECT_NE(keyed.out.find("--- ffd/state (enact.msgs.DeviceState)"), std::string::npos) << keyed.out;
  const RunResult plain = run(script + " --timeout 3");
  EXPECT_NE(plain.exit_code, 0);
  EXPECT_EQ(plain.out.find("ffd/state"), std::string::npos) << plain.out;
}

TEST_F(Access, AFloodOfParamSetFromAnOperatorKeepsTheLoopAtRate) {
  Observer obs(launcher_->endpoint(), client("bob"));
  obs.states.emplace(obs.bytes(), "ffd/state");
  obs.statuses.emplace(obs.bytes(), "node/status");
  Observed before;
  obs.observe(2.0, before);
  const double before_hz = rate_of(before.states).loop_hz;
  // 10,000 parameter changes from alice as fast as her socket takes them
  bus::AttachSender alice(launcher_->endpoint(), "flood", client("alice"));
  msgs::ParamUpdate update;
  update.set_name("sim.stiffness_n_per_m");
  update.set_number(3000.0);
  Observed during;
  int sent = 0;
  std::uint64_t id = 0;
  while (sent < 10000) {
    update.set_request_id(++id);
    if (alice.send("param/set", update)) ++sent;
    else obs.observe(0.001, during);
  }
  obs.observe(2.0, during);
  const StateRate r = rate_of(during.states);
  std::printf("[ observer ] during the flood: ffd/state %llu received, %llu lost, loop at %.0f Hz by its stamps (%.0f Hz before; %.0f nominal)\n",
              static_cast<unsigned long long>(r.received), static_cast<unsigned long long>(r.lost), r.loop_hz, before_hz, kLoopRate_hz);
  // the loop keeps its pace (generous bound: the machine is shared) and the observer its data
  EXPECT_GT(r.loop_hz, std::min(before_hz, kLoopRate_hz) * 0.8);
  EXPECT_LT(r.lost * 100, r.span);
  // the graph says it dropped alice's excess, and the simulator saw at most the limit's worth
  EXPECT_TRUE(launcher_->wait_log("dropping inbound messages from key 'alice'", 5.0)) << launcher_->log();
  // what the simulator received, from its node/status (1 Hz): wait until one counts the flood
  std::uint64_t received = 0;
  const auto take = [&](const msgs::NodeStatus& status) {
    for (const auto& t : status.topics()) {
      if (t.topic() == "param/set") received = std::max(received, t.received());
    }
  };
  for (const auto& status : during.statuses) take(status);
  if (received == 0) {
    obs.observe(10.0, during, [&](std::string_view topic) {
      if (topic == "node/status") take(during.statuses.back());
      return received == 0;
    });
  }
  std::printf("[ observer ] the simulator received %llu param/set\n", static_cast<unsigned long long>(received));
  EXPECT_GT(received, 0u) << "no node/status counted the flood's param/set";
  EXPECT_LT(received, 1000u) << "the simulator received " << received << " of 10000 param/set: the rate limit did not hold";
}

}  // namespace
}  // namespace enact::test
