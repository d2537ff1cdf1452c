#include <gtest/gtest.h>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/dynamic_message.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <thread>

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/bus/schema.h"
#include "core/bus/typed.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/graph.pb.h"
#include "tests/bus/bus_test_util.h"

namespace bus = enact::bus;
namespace msgs = enact::msgs;
namespace pb = google::protobuf;
using enact::test::eventually;
using enact::test::kWait_ms;
using enact::test::sample_state;

namespace {

// a pool holding every file of a serialized FileDescriptorSet, as a client without the
// .proto files builds it
std::unique_ptr<pb::DescriptorPool> pool_from(const std::string& descriptor_set) {
  pb::FileDescriptorSet set;
  if (!set.ParseFromString(descriptor_set)) return nullptr;
  auto pool = std::make_unique<pb::DescriptorPool>();
  for (const pb::FileDescriptorProto& file : set.file()) {
    if (pool->BuildFile(file) == nullptr) return nullptr;
  }
  return pool;
}

TEST(Schema, DescriptorSetHoldsEveryMsgsFileAfterItsImports) {
  pb::FileDescriptorSet set;
  ASSERT_TRUE(set.ParseFromString(bus::msgs_descriptor_set()));
  std::set<std::string> names;
  for (const auto& f : set.file()) {
    for (const auto& dep : f.dependency()) EXPECT_TRUE(names.contains(dep)) << f.name() << " before " << dep;
    names.insert(f.name());
  }
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(ENACT_SOURCE_DIR) / "msgs")) {
    if (entry.path().extension() != ".proto") continue;
    const std::string name = "msgs/" + entry.path().filename().string();
    EXPECT_TRUE(names.contains(name)) << name << " is missing from msgs_descriptor_set() (core/bus/schema.cpp)";
  }
  ASSERT_TRUE(pool_from(bus::msgs_descriptor_set()));
}

TEST(Schema, DescriptorSetOfOneTypeHasItsFileAndImports) {
  pb::FileDescriptorSet set;
  ASSERT_TRUE(set.ParseFromString(bus::descriptor_set_of(*msgs::DeviceState::descriptor())));
  ASSERT_EQ(set.file_size(), 2);
  EXPECT_EQ(set.file(0).name(), "msgs/common.proto");
  EXPECT_EQ(set.file(1).name(), "msgs/device_state.proto");
}

// two nodes publishing on ipc, the simulator's subscriber on the hot path, an attach point
class Graph : public ::testing::Test {
 protected:
  enact::test::TempDir dir_;
  bus::BytePublisher ffd_{bus::ipc_endpoint(dir_.path(), "ffd"), {.node = "ffd"}};
  bus::BytePublisher sim_{bus::ipc_endpoint(dir_.path(), "sim"), {.node = "sim"}};
  bus::Publisher<msgs::DeviceState> state_{ffd_, "ffd/state"};
  bus::Publisher<msgs::ForceCommand> force_{sim_, "ffd/force"};
  bus::AttachPoint attach_{"bridge-test"};

  void SetUp() override {
    attach_.add_publisher("ffd", ffd_.endpoint());
    attach_.add_publisher("sim", sim_.endpoint());
    attach_.declare_topic<msgs::DeviceState>("ffd/state", "ffd");
    attach_.declare_topic<msgs::ForceCommand>("ffd/force", "sim");
  }

  // one message on each topic; both sends must succeed
  void publish_both() {
    msgs::DeviceState s = sample_state(0.02);
    s.mutable_header()->set_stamp_ns(0);
    EXPECT_TRUE(state_.publish(s));
    msgs::ForceCommand f;
    f.set_answered_seq(state_.last_seq());
    f.mutable_force()->set_z(1.5);
    EXPECT_TRUE(force_.publish(f));
  }
};

TEST_F(Graph, LateObserverDiscoversTopicsAndSeesBothPublishersWithoutDisturbingThem) {
  // the hot path: the simulator subscribes to the FFD directly; traffic starts
  bus::ByteSubscriber sim_in;
  bus::Subscriber<msgs::DeviceState> states(sim_in, "ffd/state");
  sim_in.connect(ffd_.endpoint());
  ASSERT_TRUE(eventually([&] { return ffd_.has_subscribers("ffd/state"); }));
  for (int i = 0; i < 10; ++i) publish_both();

  // a late observer: graph/topics first, at once on subscription
  auto observer = std::make_unique<bus::ByteSubscriber>();
  bus::Subscriber<msgs::GraphInfo> graph(*observer, std::string(bus::kGraphTopic));
  observer->connect(attach_.endpoint());
  const auto info = graph.receive(3 * kWait_ms);
  ASSERT_TRUE(info);
  EXPECT_EQ(info->graph(), "bridge-test");
  ASSERT_EQ(info->topics_size(), 2);
  EXPECT_EQ(info->topics(0).name(), "ffd/state");
  EXPECT_EQ(info->topics(0).type(), "enact.msgs.DeviceState");
  EXPECT_EQ(info->topics(0).publisher(), "ffd");
  EXPECT_EQ(info->topics(1).name(), "ffd/force");
  EXPECT_EQ(info->topics(1).type(), "enact.msgs.ForceCommand");
  const auto pool = pool_from(info->descriptor_set());
  ASSERT_TRUE(pool);
  const pb::Descriptor* state_type = pool->FindMessageTypeByName("enact.msgs.DeviceState");
  ASSERT_NE(state_type, nullptr);

  // then any topic: messages of both publishers come through the attach point
  bus::ByteSubscriber data;
  data.subscribe("ffd/state");
  data.subscribe("ffd/force");
  data.connect(attach_.endpoint());
  bool got_state = false;
  bool got_force = false;
  bus::RawMessage raw;
  pb::DynamicMessageFactory factory(pool.get());
  std::unique_ptr<pb::Message> decoded(factory.GetPrototype(state_type)->New());
  ASSERT_TRUE(eventually([&] {
    publish_both();
    while (states.receive(0)) {
    }
    while (data.receive(raw, 0)) {
      if (raw.topic() == "ffd/force") got_force = true;
      if (raw.topic() != "ffd/state") continue;
      // decoded from the descriptor set alone
      EXPECT_EQ(raw.type(), "enact.msgs.DeviceState");
      EXPECT_TRUE(decoded->ParseFromArray(raw.payload(), static_cast<int>(raw.payload_size())));
      got_state = true;
    }
    return got_state && got_force;
  }));
  EXPECT_NE(decoded->DebugString().find("x: 0.02"), std::string::npos) << decoded->DebugString();

  // observers leave; the publishers and the hot path carry on untouched
  observer.reset();
  data.disconnect(attach_.endpoint());
  while (states.receive(0)) {
  }
  const std::uint64_t gaps_before = states.counters().gaps;
  for (int i = 0; i < 200; ++i) publish_both();
  for (int i = 0; i < 200; ++i) ASSERT_TRUE(states.receive(kWait_ms)) << i;
  EXPECT_EQ(states.counters().gaps, gaps_before);
  EXPECT_EQ(state_.counters().dropped, 0u);
  EXPECT_EQ(force_.counters().dropped, 0u);
}

TEST_F(Graph, GraphInfoIsRepeatedAndFollowsDeclarations) {
  bus::ByteSubscriber observer;
  bus::Subscriber<msgs::GraphInfo> graph(observer, std::string(bus::kGraphTopic));
  observer.connect(attach_.endpoint());
  const auto first = graph.receive(3 * kWait_ms);
  ASSERT_TRUE(first);
  attach_.declare_topic<msgs::DeviceState>("ffd/state_filtered", "ffd");
  // the next GraphInfo lists the new topic, without waiting for the period
  std::optional<msgs::GraphInfo> next;
  ASSERT_TRUE(eventually([&] {
    next = graph.receive(0);
    return next && next->topics_size() == 3;
  }));
  EXPECT_GT(next->header().seq(), first->header().seq());
  EXPECT_EQ(next->topics(2).name(), "ffd/state_filtered");
  EXPECT_EQ(graph.counters().malformed, 0u);
}

TEST(ObserverQueue, HoldsWhatFitsInItsBytesAtAMessagesCost) {
  EXPECT_EQ(bus::observer_queue_messages(64 << 20, 0), bus::kObserverQueue);
  EXPECT_EQ(bus::observer_queue_messages(64 << 20, 300), bus::kObserverQueue);  // small messages: the message limit
  EXPECT_EQ(bus::observer_queue_messages(64 << 20, 2000), (64 << 20) / 2000);
  EXPECT_EQ(bus::observer_queue_messages(1000, 5000), 1);
}

TEST(ObserverQueue, ItsLimitComesFromTheBytesAndEveryMessageGoesThrough) {
  enact::test::TempDir dir;
  bus::BytePublisher node(bus::ipc_endpoint(dir.path(), "node"), {.node = "node"});
  bus::AttachPoint attach("queue-test", {.observer_queue_bytes = 1 << 20});
  attach.add_publisher("node", node.endpoint());
  EXPECT_EQ(attach.observer_queue(), static_cast<int>((1u << 20) / bus::kMeanCost_bytes));
  bus::ByteSubscriber reader;
  reader.subscribe("big");
  reader.connect(attach.endpoint());
  ASSERT_TRUE(eventually([&] { return node.has_subscribers("big"); }));
  // 10 kB messages, more than the limit: a reader that keeps up loses none of them
  const std::string payload(10'000, 'x');
  bus::RawMessage m;
  int read = 0;
  const int sent = 2 * attach.observer_queue();
  for (int i = 0; i < sent; ++i) {
    ASSERT_TRUE(node.send("big", "raw", payload.data(), payload.size()));
    while (reader.receive(m, 0)) ++read;
    std::this_thread::sleep_for(std::chrono::microseconds(300));
  }
  ASSERT_TRUE(eventually([&] {
    while (reader.receive(m, 0)) ++read;
    return read == sent;
  })) << read;
}

TEST(ObserverQueue, AFewLargeMessagesInAStreamOfSmallOnesKeepTheQueueDeep) {
  // a parameter listing of kB once a second among 5 kHz states of tens of bytes: when the
  // limit followed the largest message's cost, changing it for the connected observer
  // stalled its stream (a logger saw gaps a second into a run)
  enact::test::TempDir dir;
  bus::BytePublisher node(bus::ipc_endpoint(dir.path(), "node"), {.node = "node"});
  bus::AttachPoint attach("queue-test", {});  // the default 64 MB
  attach.add_publisher("node", node.endpoint());
  bus::ByteSubscriber reader;
  reader.subscribe("small");
  reader.subscribe("large");
  reader.connect(attach.endpoint());
  ASSERT_TRUE(eventually([&] { return node.has_subscribers("small") && node.has_subscribers("large"); }));
  const std::string small(40, 's'), large(10'000, 'L');
  bus::RawMessage m;
  int read = 0;
  for (int i = 0; i < 600; ++i) {
    const std::string& payload = i % 200 == 0 ? large : small;
    ASSERT_TRUE(node.send(i % 200 == 0 ? "large" : "small", "raw", payload.data(), payload.size()));
    while (reader.receive(m, 0)) ++read;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  ASSERT_TRUE(eventually([&] {
    while (reader.receive(m, 0)) ++read;
    return read == 600;
  })) << read;
  EXPECT_EQ(attach.observer_queue(), bus::kObserverQueue);
}

TEST_F(Graph, GraphInfoCarriesTheNameGivenLater) {
  bus::ByteSubscriber observer;
  bus::Subscriber<msgs::GraphInfo> graph(observer, std::string(bus::kGraphTopic));
  observer.connect(attach_.endpoint());
  const auto first = graph.receive(3 * kWait_ms);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->graph(), "bridge-test");
  attach_.set_graph_name("bridge-test-2");
  // the next GraphInfo has the new name, without waiting for the period
  std::optional<msgs::GraphInfo> next;
  ASSERT_TRUE(eventually([&] {
    next = graph.receive(0);
    return next && next->graph() == "bridge-test-2";
  }));
  EXPECT_EQ(next->topics_size(), 2);
}

TEST_F(Graph, StopIsCleanAndIdempotent) {
  attach_.stop();
  attach_.stop();
  EXPECT_THROW(attach_.declare_topic("x", "y", "z"), std::logic_error);
}

TEST_F(Graph, PythonClientDecodesTheBus) {
  const std::string python = "/usr/bin/python3";
  if (enact::test::run(python + " -c 'import zmq, google.protobuf'").exit_code != 0) {
    GTEST_SKIP() << "python3-zmq or python3-protobuf not installed";
  }
  // the nodes keep publishing on their own thread while the script runs
  std::atomic<bool> done = false;
  std::thread nodes([&] {
    while (!done) {
      publish_both();
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  const auto r = enact::test::run(python + " " + enact::test::source_path("scripts/attach_example.py") + " " +
                                  attach_.endpoint() + " ffd/state --count 3 --timeout 10");
  done = true;
  nodes.join();
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("graph bridge-test"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ffd/state  enact.msgs.DeviceState  from ffd"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("x: 0.02"), std::string::npos) << r.out;
}

}  // namespace
