// What observers send through the attach point: messages on inbound topics reach the nodes
// (and the observers of that topic); anything else is dropped; data still flows to observers.
#include <gtest/gtest.h>

#include <string>

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/bus/typed.h"
#include "msgs/device_state.pb.h"
#include "msgs/param_update.pb.h"
#include "tests/bus/bus_test_util.h"

namespace bus = enact::bus;
namespace msgs = enact::msgs;
using enact::test::eventually;

namespace {

// an attach point with an inbound publisher for param/set, a node subscribed to it, an
// observer sending and a second observer listening
class Inbound : public ::testing::Test {
 protected:
  enact::test::TempDir dir_;
  bus::AttachPoint attach_{"inbound-test", {.inbound_endpoint = bus::ipc_endpoint(dir_.path(), "attach:in"), .inbound_topics = {"param/set"}}};
  bus::ByteSubscriber node_bytes_;
  bus::Subscriber<msgs::ParamUpdate> node_{node_bytes_, "param/set"};
  bus::AttachSender sender_{attach_.endpoint(), "viewer"};

  void SetUp() override { node_bytes_.connect(bus::ipc_endpoint(dir_.path(), "attach:in")); }

  // sends `msg` on `topic` until the node receives a ParamUpdate (the connections come up
  // asynchronously: a sender repeats until answered), or gives up
  bool send_until_received(const std::string& topic, msgs::ParamUpdate msg, msgs::ParamUpdate& got) {
    return eventually([&] {
      sender_.send(topic, msg);
      return node_.receive(got, 20);
    });
  }
};

TEST_F(Inbound, ParamSetReachesTheNodesWithItsHeader) {
  msgs::ParamUpdate update;
  update.set_name("sim.stiffness_n_per_m");
  update.set_number(4000.0);
  update.set_request_id(42);
  msgs::ParamUpdate got;
  ASSERT_TRUE(send_until_received("param/set", update, got));
  EXPECT_EQ(got.name(), "sim.stiffness_n_per_m");
  EXPECT_EQ(got.number(), 4000.0);
  EXPECT_EQ(got.request_id(), 42u);
  EXPECT_EQ(got.header().source(), "viewer");
  EXPECT_GE(got.header().seq(), 1u);
}

TEST_F(Inbound, OtherTopicsFromObserversAreDropped) {
  // once param/set is known to get through, a message on another topic sent before it is not
  msgs::ParamUpdate probe;
  probe.set_name("probe");
  msgs::ParamUpdate got;
  ASSERT_TRUE(send_until_received("param/set", probe, got));
  bus::ByteSubscriber raw_node;
  raw_node.subscribe("param/set");
  raw_node.subscribe("ffd/force");
  raw_node.connect(bus::ipc_endpoint(dir_.path(), "attach:in"));
  // give the new connection the time the first one took, with traffic on both topics
  int param_seen = 0, other_seen = 0;
  msgs::ParamUpdate stray;
  stray.set_name("stray");
  ASSERT_TRUE(eventually([&] {
    sender_.send("ffd/force", stray);
    sender_.send("param/set", probe);
    while (const auto m = raw_node.receive(5)) {
      param_seen += m->topic() == "param/set";
      other_seen += m->topic() != "param/set";
    }
    return param_seen >= 3;
  }));
  EXPECT_EQ(other_seen, 0);
}

TEST_F(Inbound, ObserversOfTheTopicSeeItToo) {
  bus::ByteSubscriber logger_bytes;
  bus::Subscriber<msgs::ParamUpdate> logger(logger_bytes, "param/set");
  logger_bytes.connect(attach_.endpoint());
  msgs::ParamUpdate update;
  update.set_name("sim.reset");
  update.set_flag(true);
  msgs::ParamUpdate got;
  ASSERT_TRUE(eventually([&] {
    sender_.send("param/set", update);
    return logger.receive(got, 20);
  }));
  EXPECT_EQ(got.name(), "sim.reset");
}

TEST(InboundOff, WithoutAnInboundEndpointNothingIsRepublishedAndDataStillFlows) {
  enact::test::TempDir dir;
  bus::BytePublisher ffd(bus::ipc_endpoint(dir.path(), "ffd"), {.node = "ffd"});
  bus::Publisher<msgs::DeviceState> states(ffd, "ffd/state");
  bus::AttachPoint attach("no-inbound", {.inbound_topics = {"param/set"}});
  attach.add_publisher("ffd", ffd.endpoint());
  bus::ByteSubscriber observer_bytes;
  bus::Subscriber<msgs::DeviceState> observer(observer_bytes, "ffd/state");
  bus::ByteSubscriber param_bytes;
  bus::Subscriber<msgs::ParamUpdate> param_observer(param_bytes, "param/set");
  observer_bytes.connect(attach.endpoint());
  param_bytes.connect(attach.endpoint());
  bus::AttachSender sender(attach.endpoint(), "viewer");
  msgs::ParamUpdate update;
  update.set_name("sim.reset");
  msgs::DeviceState state = enact::test::sample_state(0.001);
  msgs::DeviceState got;
  // the observer's data arrives while the sender keeps sending: the sends were handled
  ASSERT_TRUE(eventually([&] {
    sender.send("param/set", update);
    states.publish(state);
    return observer.receive(got, 20);
  }));
  msgs::ParamUpdate none;
  EXPECT_FALSE(param_observer.receive(none, 200));
}

}  // namespace
