// The attach point's latched state topics: a late observer gets the last message at once,
// without the publisher sending it again; other topics are not repeated.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/bus/typed.h"
#include "msgs/device_state.pb.h"
#include "msgs/task_event.pb.h"
#include "tests/bus/bus_test_util.h"

namespace bus = enact::bus;
namespace msgs = enact::msgs;
using enact::test::eventually;

namespace {

class Latched : public ::testing::Test {
 protected:
  enact::test::TempDir dir_;
  bus::BytePublisher node_{bus::ipc_endpoint(dir_.path(), "sim"), {.node = "sim"}};
  bus::Publisher<msgs::TaskEvent> state_{node_, "task/state"};
  bus::Publisher<msgs::DeviceState> stream_{node_, "ffd/state"};
  bus::AttachPoint attach_{"latched-test", {.latched_topics = {"task/state"}}};

  void SetUp() override {
    attach_.add_publisher("sim", node_.endpoint());
    // the attach point subscribes to the state topic by itself, before any observer
    ASSERT_TRUE(eventually([&] { return node_.has_subscribers("task/state"); }));
  }
};

// an observer that subscribes to `topic` and waits up to `wait_ms` for one message
template <class Msg>
bool first_message(const std::string& endpoint, const std::string& topic, Msg& out, int wait_ms) {
  bus::ByteSubscriber bytes;
  bus::Subscriber<Msg> sub(bytes, topic);
  bytes.connect(endpoint);
  return sub.receive(out, wait_ms);
}

TEST_F(Latched, ALateObserverGetsTheLastStateAtOnceAndOnlyThat) {
  msgs::TaskEvent e;
  e.set_detail("first");
  state_.publish(e);
  e.set_detail("second");
  state_.publish(e);
  msgs::DeviceState s;
  stream_.publish(s);
  // published long before the observer comes; never published again
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  msgs::TaskEvent got;
  ASSERT_TRUE(first_message(attach_.endpoint(), "task/state", got, 2000));
  EXPECT_EQ(got.detail(), "second");
  EXPECT_EQ(got.header().seq(), 2u);
  // a stream topic is not kept
  msgs::DeviceState none;
  EXPECT_FALSE(first_message(attach_.endpoint(), "ffd/state", none, 300));
}

TEST_F(Latched, AnObserverLeavingDoesNotEndTheAttachPointsOwnSubscription) {
  msgs::TaskEvent got;
  {
    msgs::TaskEvent e;
    e.set_detail("before");
    state_.publish(e);
    ASSERT_TRUE(eventually([&] { return first_message(attach_.endpoint(), "task/state", got, 200); }));
  }
  // the observer is gone (its unsubscription reached the attach point); a new state still
  // reaches the attach point and the next late observer
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  msgs::TaskEvent e;
  e.set_detail("after");
  state_.publish(e);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_TRUE(first_message(attach_.endpoint(), "task/state", got, 2000));
  EXPECT_EQ(got.detail(), "after");
}

}  // namespace
