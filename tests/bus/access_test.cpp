// Keys, access files and CURVE on the attach point: only listed keys connect, a wrong server
// key or a missing key is said, observers are refused param/set with an answer, operators'
// messages pass stamped with their key's name, and a flood is cut at the rate limit.
#include <sys/stat.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "core/bus/access.h"
#include "core/bus/attach.h"
#include "core/bus/client.h"
#include "core/bus/keys.h"
#include "core/config/yaml.h"
#include "msgs/device_state.pb.h"
#include "msgs/param_update.pb.h"
#include "tests/bus/bus_test_util.h"

namespace bus = enact::bus;
namespace msgs = enact::msgs;
using enact::config::Error;
using enact::test::eventually;

namespace {

// the message of the config::Error `f` throws ("" when it throws none)
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Keys, NewPairIsWrittenPrivateAndNeverOverwritten) {
  enact::test::TempDir dir;
  const bus::KeyPair pair = bus::write_key_pair(dir.path() + "/keys", "lab");
  struct stat st{};
  ASSERT_EQ(stat((dir.path() + "/keys/lab.key").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  EXPECT_EQ(bus::read_key_file(dir.path() + "/keys/lab.key", "key"), pair.secret_z85);
  EXPECT_EQ(bus::read_key_file(dir.path() + "/keys/lab.pub", "key"), pair.public_z85);
  // the public key of the secret file is the .pub file's
  EXPECT_EQ(bus::read_public_key(dir.path() + "/keys/lab.key", "key"), pair.public_z85);
  EXPECT_NE(pair.public_z85, pair.secret_z85);
  EXPECT_NE(error_of([&] { bus::write_key_pair(dir.path() + "/keys", "lab"); }).find("never overwritten"), std::string::npos);
  EXPECT_EQ(bus::read_key_file(dir.path() + "/keys/lab.key", "key"), pair.secret_z85);
}

TEST(Keys, ASecretKeyOthersCanReadIsRefused) {
  enact::test::TempDir dir;
  bus::write_key_pair(dir.path(), "lab");
  chmod((dir.path() + "/lab.key").c_str(), 0644);
  EXPECT_NE(error_of([&] { bus::read_key_file(dir.path() + "/lab.key", "--key"); }).find("chmod 600"), std::string::npos);
  enact::test::write_file(dir.file("bad.pub"), "# a comment\nnot a key\n");
  EXPECT_NE(error_of([&] { bus::read_key_file(dir.file("bad.pub"), "--server-key"); }).find("bad.pub:2:"), std::string::npos);
}

// keys of a graph and three clients, and an access file naming two of them
class Keyed : public ::testing::Test {
 protected:
  enact::test::TempDir dir_;
  bus::KeyPair server_ = bus::write_key_pair(dir_.path(), "graph");
  bus::KeyPair alice_ = bus::write_key_pair(dir_.path(), "alice");
  bus::KeyPair bob_ = bus::write_key_pair(dir_.path(), "bob");
  bus::KeyPair mallory_ = bus::write_key_pair(dir_.path(), "mallory");
  std::vector<std::string> log_;
  std::mutex log_mutex_;

  std::string access_file(const std::string& extra = "") {
    enact::test::write_file(dir_.file("access.yaml"), "server_key: graph.key\n" + extra +
                                                          "clients:\n"
                                                          "  - {name: alice, public_key_file: alice.pub, role: operate}\n"
                                                          "  - {name: bob, public_key: \"" + bob_.public_z85 + "\", role: observe}\n");
    return dir_.file("access.yaml");
  }
  bus::ClientKeys keys(const std::string& who, const std::string& server = "graph.pub") {
    return bus::client_keys(dir_.file(who + ".key"), dir_.file(server));
  }
  bus::AttachOptions options(const std::string& extra = "") {
    bus::AttachOptions o;
    o.access = bus::load_access(access_file(extra));
    o.inbound_endpoint = bus::ipc_endpoint(dir_.path(), "attach:in");
    o.inbound_topics = {"param/set"};
    o.log = [this](const std::string& line) {
      const std::lock_guard lock(log_mutex_);
      log_.push_back(line);
    };
    return o;
  }
  std::vector<std::string> log() {
    const std::lock_guard lock(log_mutex_);
    return log_;
  }
};

TEST_F(Keyed, AccessFileErrorsNameTheLineAndTheFix) {
  const std::string bad_role = error_of([&] {
    enact::test::write_file(dir_.file("a.yaml"), "server_key: graph.key\nclients:\n  - {name: alice, public_key_file: alice.pub, role: admin}\n");
    bus::load_access(dir_.file("a.yaml"));
  });
  EXPECT_NE(bad_role.find("a.yaml:3:"), std::string::npos) << bad_role;
  EXPECT_NE(bad_role.find("role: observe"), std::string::npos) << bad_role;
  const std::string missing_key = error_of([&] {
    enact::test::write_file(dir_.file("b.yaml"), "server_key: graph.key\nclients:\n  - {name: x, public_key_file: nobody.pub, role: observe}\n");
    bus::load_access(dir_.file("b.yaml"));
  });
  EXPECT_NE(missing_key.find("b.yaml:3:"), std::string::npos) << missing_key;
  EXPECT_NE(missing_key.find("nobody.pub"), std::string::npos) << missing_key;
  const std::string twice = error_of([&] {
    enact::test::write_file(dir_.file("c.yaml"), "server_key: graph.key\nclients:\n  - {name: a, public_key_file: alice.pub, role: observe}\n  - {name: b, public_key_file: alice.pub, role: operate}\n");
    bus::load_access(dir_.file("c.yaml"));
  });
  EXPECT_NE(twice.find("c.yaml:4:"), std::string::npos) << twice;
  const bus::Access a = bus::load_access(access_file());
  ASSERT_EQ(a.clients.size(), 2u);
  EXPECT_EQ(a.server_public_z85, server_.public_z85);
  EXPECT_EQ(a.find("alice")->role, bus::Role::operate);
  EXPECT_EQ(a.find("bob")->public_z85, bob_.public_z85);
}

TEST_F(Keyed, TheShippedExampleLoadsWithKeysInTheHomeFolder) {
  // its paths start at ~/.config/enact/keys: make those keys in a home of our own
  const std::string home = std::getenv("HOME") ? std::getenv("HOME") : "";
  setenv("HOME", dir_.path().c_str(), 1);
  bus::write_key_pair(dir_.path() + "/.config/enact/keys", "lab-graph");
  const bus::KeyPair logger = bus::write_key_pair(dir_.path() + "/.config/enact/keys", "lab-logger");
  const std::string error = error_of([&] {
    const bus::Access a = bus::load_access(enact::test::source_path("launch/access.example.yaml"));
    ASSERT_EQ(a.clients.size(), 2u);
    EXPECT_EQ(a.find("lab-logger")->public_z85, logger.public_z85);
    EXPECT_EQ(a.find("experimenter-laptop")->role, bus::Role::operate);
  });
  setenv("HOME", home.c_str(), 1);
  EXPECT_EQ(error, "");
}

TEST_F(Keyed, RemoteBindNeedsAnAccessFile) {
  bus::AttachOptions plain;
  plain.bind_endpoint = "tcp://0.0.0.0:*";
  plain.allow_remote = true;
  EXPECT_NE(error_of([&] { bus::AttachPoint ap("g", plain); }).find("no access file"), std::string::npos);
  bus::AttachOptions keyed = options();
  keyed.bind_endpoint = "tcp://0.0.0.0:*";
  keyed.allow_remote = true;
  EXPECT_NO_THROW(bus::AttachPoint ap("g", std::move(keyed)));
}

TEST_F(Keyed, OnlyListedKeysConnectAndAWrongServerKeyIsSaid) {
  bus::AttachPoint attach("keyed", options());
  // a listed key: the handshake succeeds, GraphInfo arrives
  bus::ByteSubscriber bob;
  bob.subscribe("graph/topics");
  EXPECT_NO_THROW(bus::attach_connect(bob.socket(), attach.endpoint(), keys("bob")));
  EXPECT_TRUE(bob.receive(enact::test::kWait_ms).has_value());
  // no key: told the graph requires keys, and nothing arrives in 3 s
  bus::ByteSubscriber nobody;
  nobody.subscribe("graph/topics");
  EXPECT_NE(error_of([&] { bus::attach_connect(nobody.socket(), attach.endpoint(), {}); }).find("requires keys"), std::string::npos);
  EXPECT_FALSE(nobody.receive(3000).has_value());
  // a key not in the access file: refused, and logged with its fingerprint
  bus::ByteSubscriber mallory;
  mallory.subscribe("graph/topics");
  EXPECT_NE(error_of([&] { bus::attach_connect(mallory.socket(), attach.endpoint(), keys("mallory")); }).find("refused this key"), std::string::npos);
  EXPECT_FALSE(mallory.receive(500).has_value());
  ASSERT_TRUE(eventually([&] { return !log().empty(); }));
  EXPECT_NE(log()[0].find(bus::fingerprint(mallory_.public_z85)), std::string::npos) << log()[0];
  // once per key per minute: a second attempt is not logged again
  bus::ByteSubscriber again;
  (void)error_of([&] { bus::attach_connect(again.socket(), attach.endpoint(), keys("mallory")); });
  EXPECT_EQ(log().size(), 1u);
  // the right client key with a wrong server key: the handshake fails, and says so
  bus::ByteSubscriber wrong;
  const std::string e = error_of([&] { bus::attach_connect(wrong.socket(), attach.endpoint(), keys("bob", "alice.pub")); });
  EXPECT_NE(e.find("--server-key"), std::string::npos) << e;
}

TEST_F(Keyed, ObserversAreRefusedAndOperatorsStampedWithTheirKeyName) {
  bus::AttachPoint attach("keyed", options());
  bus::ByteSubscriber node_bytes;
  bus::Subscriber<msgs::ParamUpdate> node(node_bytes, "param/set");
  node_bytes.connect(bus::ipc_endpoint(dir_.path(), "attach:in"));
  // bob (observe) listens to the answers, and sends
  bus::ByteSubscriber bob_bytes;
  bus::Subscriber<msgs::ParamAck> acks(bob_bytes, "param/ack");
  bus::attach_connect(bob_bytes.socket(), attach.endpoint(), keys("bob"));
  bus::AttachSender bob(attach.endpoint(), "bob-viewer", keys("bob"));
  msgs::ParamUpdate update;
  update.set_name("sim.stiffness_n_per_m");
  update.set_number(4000.0);
  update.set_request_id(7);
  msgs::ParamAck ack;
  ASSERT_TRUE(eventually([&] {
    bob.send("param/set", update);
    return acks.receive(ack, 20);
  }));
  EXPECT_FALSE(ack.applied());
  EXPECT_EQ(ack.request_id(), 7u);
  EXPECT_NE(ack.reason().find("observe"), std::string::npos) << ack.reason();
  msgs::ParamUpdate got;
  EXPECT_FALSE(node.receive(got, 200));
  // alice (operate) gets through, her key's name stamped over the one she claims
  bus::AttachSender alice(attach.endpoint(), "alice-cli", keys("alice"));
  update.mutable_header()->set_sender_key("bob");
  ASSERT_TRUE(eventually([&] {
    update.mutable_header()->set_sender_key("bob");
    alice.send("param/set", update);
    return node.receive(got, 20);
  }));
  EXPECT_EQ(got.header().sender_key(), "alice");
  EXPECT_EQ(got.header().source(), "alice-cli");
  EXPECT_EQ(got.number(), 4000.0);
}

TEST_F(Keyed, AFloodIsCutAtTheRateLimitAndCounted) {
  bus::AttachPoint attach("keyed", options("inbound_rate_per_s: 50\n"));
  bus::ByteSubscriber node_bytes;
  bus::Subscriber<msgs::ParamUpdate> node(node_bytes, "param/set");
  node_bytes.set_receive_hwm(100000);
  node_bytes.connect(bus::ipc_endpoint(dir_.path(), "attach:in"));
  bus::AttachSender alice(attach.endpoint(), "alice-cli", keys("alice"));
  msgs::ParamUpdate update;
  update.set_name("sim.reset");
  update.set_flag(true);
  // wait for the path to be up, then 5000 at once
  msgs::ParamUpdate got;
  ASSERT_TRUE(eventually([&] {
    alice.send("param/set", update);
    return node.receive(got, 20);
  }));
  while (node.receive(got, 100)) {
  }
  const auto start = std::chrono::steady_clock::now();
  int sent = 0;
  for (int i = 0; i < 5000; ++i) sent += alice.send("param/set", update);
  int passed = 0;
  while (node.receive(got, 500)) ++passed;
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_GT(sent, 4000);
  // at most the bucket (50) plus what the elapsed time refilled, and the rest said
  EXPECT_LE(passed, 50 + static_cast<int>(elapsed_s * 50) + 1);
  EXPECT_GE(passed, 40);
  ASSERT_TRUE(eventually([&] {
    for (const auto& line : log()) {
      if (line.find("dropped") != std::string::npos && line.find("alice") != std::string::npos) return true;
    }
    return false;
  }));
}

}  // namespace
