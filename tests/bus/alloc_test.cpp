#include <gtest/gtest.h>

#include <cstddef>
#include <iostream>

#include "core/bus/bytes.h"
#include "core/bus/typed.h"
#include "msgs/device_state.pb.h"
#include "tests/bus/bus_test_util.h"
#include "tests/support/alloc_guard.h"

namespace bus = enact::bus;
namespace msgs = enact::msgs;
using enact::test::eventually;
using enact::test::kWait_ms;

namespace {

// heap allocations made by publish() (this thread only), over `count` steady-state messages
// of a fixed size, each received (outside the count) before the next is published
std::size_t publish_allocations(const char* endpoint, msgs::DeviceState m, int count) {
  bus::BytePublisher pub(endpoint, {.node = "ffd"});
  bus::ByteSubscriber bytes;
  bus::Subscriber<msgs::DeviceState> sub(bytes, "ffd/state");
  bytes.connect(pub.endpoint());
  EXPECT_TRUE(eventually([&] { return pub.has_subscribers("ffd/state"); }));
  bus::Publisher<msgs::DeviceState> typed(pub, "ffd/state");
  msgs::DeviceState in;
  // warm-up: buffers, counters, the header's source, seq up to two varint bytes
  for (int i = 0; i < 1000; ++i) {
    EXPECT_TRUE(typed.publish(m));
    EXPECT_TRUE(sub.receive(in, kWait_ms));
  }
  std::size_t allocations = 0;
  for (int i = 0; i < count; ++i) {
    {
      const enact::test::AllocGuard guard;
      EXPECT_TRUE(typed.publish(m));
      allocations += guard.allocations();
    }
    EXPECT_TRUE(sub.receive(in, kWait_ms));
  }
  return allocations;
}

TEST(BusAlloc, PublishOfASmallMessageAllocatesNothing) {
  // 18 bytes serialised: ZeroMQ keeps frames up to 33 bytes inside the message itself
  msgs::DeviceState m;
  m.mutable_header()->set_stamp_ns(1'000'000'000);
  m.set_buttons(1);
  ASSERT_LE(m.ByteSizeLong() + 8, 33u);
  EXPECT_EQ(publish_allocations("inproc://bus-alloc-small", m, 1000), 0u);
}

TEST(BusAlloc, PublishOfALargerMessageAllocatesOnlyZeroMqsFrameCopy) {
  // ~80 bytes: libzmq copies a frame over 33 bytes into one malloc'ed block per send
  // (zmq_msg_init_size); the typed layer itself adds nothing
  msgs::DeviceState m = enact::test::sample_state(0.01);
  m.mutable_header()->set_stamp_ns(1'700'000'000'000'000);
  constexpr int kCount = 1000;
  const std::size_t allocations = publish_allocations("inproc://bus-alloc-large", m, kCount);
  std::cout << "[ measured ] " << m.ByteSizeLong() << "-byte DeviceState: " << allocations << " allocations in "
            << kCount << " publishes\n";
  RecordProperty("allocations_per_1000_publishes", static_cast<int>(allocations));
  EXPECT_LE(allocations, static_cast<std::size_t>(kCount));
}

}  // namespace
