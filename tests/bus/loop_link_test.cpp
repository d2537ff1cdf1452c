// LoopLink: the loop's same-host hop between the FFD driver (it listens) and the simulator.
#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <string>
#include <thread>

#include "core/bus/loop_link.h"
#include "core/bus/typed.h"
#include "msgs/device_state.pb.h"
#include "core/config/yaml.h"
#include "core/rt/clock.h"
#include "tests/bus/bus_test_util.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/test_util.h"

namespace enact::bus {
namespace {

using test::TempDir;

constexpr std::int64_t kSecond_ns = 1'000'000'000;

// a master and a connected follower in `dir`
struct Pair {
  LoopLink master, follower;
  explicit Pair(const TempDir& dir) {
    master = LoopLink::listen(loop_link_path(dir.path(), "ffd"));
    follower = LoopLink::connect(master.path(), rt::now_ns() + kSecond_ns);
    master.wait_for_peer(rt::now_ns() + kSecond_ns);
  }
};

TEST(LoopLink, MessagesKeepTheirBoundariesBothWays) {
  TempDir dir;
  Pair p(dir);
  ASSERT_TRUE(p.master.connected());
  ASSERT_TRUE(p.follower.connected());
  ASSERT_TRUE(p.master.send("state-1", 7));
  ASSERT_TRUE(p.master.send("state-22", 8));
  char buf[LoopLink::kMaxMessage];
  ASSERT_EQ(p.follower.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), 7);
  EXPECT_EQ(std::string(buf, 7), "state-1");
  ASSERT_EQ(p.follower.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), 8);
  EXPECT_EQ(std::string(buf, 8), "state-22");
  ASSERT_TRUE(p.follower.send("force", 5));
  ASSERT_EQ(p.master.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), 5);
  EXPECT_EQ(std::string(buf, 5), "force");
  EXPECT_EQ(p.master.counters().sent, 2u);
  EXPECT_EQ(p.master.counters().received, 1u);
  EXPECT_EQ(p.follower.counters().received, 2u);
}

TEST(LoopLink, ReceiveWaitsUntilItsDeadlineAndNoLonger) {
  TempDir dir;
  Pair p(dir);
  char buf[64];
  const std::int64_t deadline = rt::now_ns() + 20'000'000;
  EXPECT_EQ(p.master.receive(buf, sizeof buf, deadline), 0);
  const std::int64_t returned = rt::now_ns();
  EXPECT_GE(returned, deadline);
  EXPECT_LT(returned, deadline + kSecond_ns);  // not a blocking read
  EXPECT_TRUE(p.master.connected());
  // a message that comes while it waits ends the wait at once
  std::thread later([&] {
    rt::sleep_until_ns(rt::now_ns() + 5'000'000);
    p.follower.send("x", 1);
  });
  EXPECT_EQ(p.master.receive(buf, sizeof buf, rt::now_ns() + 10 * kSecond_ns), 1);
  later.join();
}

TEST(LoopLink, AWaitEndsWhenItsStopDescriptorIsReadableLongBeforeItsDeadline) {
  TempDir dir;
  Pair p(dir);
  char buf[64];
  const int stop = eventfd(0, EFD_CLOEXEC);
  ASSERT_GE(stop, 0);
  // a message waiting is read whatever the stop descriptor says
  ASSERT_TRUE(p.follower.send("x", 1));
  std::uint64_t one = 1;
  ASSERT_EQ(write(stop, &one, sizeof one), static_cast<ssize_t>(sizeof one));
  EXPECT_EQ(p.master.receive(buf, sizeof buf, rt::now_ns() + 10 * kSecond_ns, stop), 1);
  // none waiting: the readable stop descriptor ends the wait at once, not the deadline 10 s on
  const std::int64_t before = rt::now_ns();
  EXPECT_EQ(p.master.receive(buf, sizeof buf, before + 10 * kSecond_ns, stop), 0);
  EXPECT_LT(rt::now_ns() - before, 5 * kSecond_ns);
  EXPECT_TRUE(p.master.connected());
  // one that becomes readable while it waits ends it then
  std::uint64_t taken = 0;
  ASSERT_EQ(read(stop, &taken, sizeof taken), static_cast<ssize_t>(sizeof taken));
  std::thread later([&] {
    rt::sleep_until_ns(rt::now_ns() + 20'000'000);
    ASSERT_EQ(write(stop, &one, sizeof one), static_cast<ssize_t>(sizeof one));
  });
  const std::int64_t waited = rt::now_ns();
  EXPECT_EQ(p.master.receive(buf, sizeof buf, waited + 10 * kSecond_ns, stop), 0);
  EXPECT_GE(rt::now_ns() - waited, 20'000'000);
  EXPECT_LT(rt::now_ns() - waited, 5 * kSecond_ns);
  later.join();
  close(stop);
}

TEST(LoopLink, AFollowerThatLeavesIsSeenAndANewOneTakesItsPlace) {
  TempDir dir;
  Pair p(dir);
  p.follower = LoopLink();  // the simulator dies
  char buf[64];
  EXPECT_EQ(p.master.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), -1);
  EXPECT_FALSE(p.master.connected());
  EXPECT_FALSE(p.master.send("lost", 4));
  EXPECT_EQ(p.master.counters().dropped, 1u);
  // it is respawned and connects again
  LoopLink again = LoopLink::connect(p.master.path(), rt::now_ns() + kSecond_ns);
  ASSERT_TRUE(again.connected());
  EXPECT_TRUE(p.master.wait_for_peer(rt::now_ns() + kSecond_ns));
  ASSERT_TRUE(p.master.send("hello", 5));
  EXPECT_EQ(again.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), 5);
  EXPECT_EQ(p.master.counters().peers, 2u);
}

TEST(LoopLink, MessagesOfEverySizeComeWholeAndInOrderRoundTheRingManyTimes) {
  TempDir dir;
  Pair p(dir);
  // sizes from 1 byte to the largest, each filled with its own pattern; some 40 MB in all go
  // round the 128 KiB ring hundreds of times, so records meet its end at every offset
  char out[LoopLink::kMaxMessage], in[LoopLink::kMaxMessage];
  std::size_t total = 0;
  for (std::size_t i = 0; i < 20'000; ++i) {
    const std::size_t size = 1 + (i * 2654435761u) % LoopLink::kMaxMessage;
    for (std::size_t b = 0; b < size; ++b) out[b] = static_cast<char>(i + b * 7);
    ASSERT_TRUE(p.master.send(out, size)) << "message " << i;
    if (i % 3 == 0) continue;  // a few left queued each time: the reader trails the writer
    for (int k = 0; k < (i % 3 == 2 ? 2 : 1) && total < i + 1; ++k, ++total) {
      const std::size_t want = 1 + (total * 2654435761u) % LoopLink::kMaxMessage;
      ASSERT_EQ(p.follower.receive(in, sizeof in, rt::now_ns() + kSecond_ns), static_cast<long>(want)) << "message " << total;
      for (std::size_t b = 0; b < want; ++b) ASSERT_EQ(in[b], static_cast<char>(total + b * 7)) << "message " << total << " byte " << b;
    }
  }
  EXPECT_EQ(p.master.counters().dropped, 0u);
  EXPECT_EQ(p.follower.counters().received, total);
}

TEST(LoopLink, AReaderThatSleepsIsWokenAndOneThatFindsItsMessageCostsNoDoorbell) {
  TempDir dir;
  Pair p(dir);
  char buf[64];
  // the follower is not waiting: messages wait in the ring, no doorbell rung
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(p.master.send("s", 1));
  for (int i = 0; i < 10; ++i) ASSERT_EQ(p.follower.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), 1);
  EXPECT_EQ(p.master.counters().doorbells, 0u);
  // the follower sleeps in receive: the send rings it, and it wakes long before its deadline
  std::int64_t woke = 0;
  long got = 0;
  std::thread reader([&] {
    got = p.follower.receive(buf, sizeof buf, rt::now_ns() + 20 * kSecond_ns);
    woke = rt::now_ns();
  });
  rt::sleep_until_ns(rt::now_ns() + 200'000'000);  // asleep in its wait by now
  const std::int64_t sent = rt::now_ns();
  ASSERT_TRUE(p.master.send("late", 4));
  reader.join();
  EXPECT_EQ(got, 4);
  EXPECT_LT(woke - sent, 10 * kSecond_ns) << "the reader slept to its deadline: no doorbell";
  EXPECT_EQ(p.master.counters().doorbells, 1u);
}

TEST(LoopLink, WhatAFollowerSentBeforeItLeftIsReadBeforeItsEnd) {
  TempDir dir;
  Pair p(dir);
  ASSERT_TRUE(p.follower.send("last", 4));
  p.follower = LoopLink();
  char buf[64];
  EXPECT_EQ(p.master.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), 4);
  EXPECT_EQ(p.master.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), -1);
  EXPECT_FALSE(p.master.connected());
}

TEST(LoopLink, AStrangerOnTheSocketIsRefusedAndTheRealFollowerTakenAfter) {
  TempDir dir;
  LoopLink master = LoopLink::listen(loop_link_path(dir.path(), "ffd"));
  // a process that connects and sends words but no shared memory (not a loop link, or an old one)
  const int stranger = socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, master.path().c_str(), sizeof addr.sun_path - 1);
  ASSERT_EQ(::connect(stranger, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  ASSERT_EQ(::send(stranger, "hello", 5, 0), 5);
  EXPECT_FALSE(master.wait_for_peer(rt::now_ns() + 50'000'000));
  EXPECT_FALSE(master.connected());
  char none[8];
  EXPECT_EQ(recv(stranger, none, sizeof none, MSG_DONTWAIT), 0) << "the stranger's connection was not closed";
  close(stranger);
  // one that connects and says nothing does not hold the master either
  const int silent = socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
  ASSERT_EQ(::connect(silent, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  const std::int64_t before = rt::now_ns();
  EXPECT_FALSE(master.accept_peer());
  EXPECT_LT(rt::now_ns() - before, kSecond_ns);
  // the real follower comes after it and is taken
  LoopLink follower = LoopLink::connect(master.path(), rt::now_ns() + kSecond_ns);
  ASSERT_TRUE(master.wait_for_peer(rt::now_ns() + kSecond_ns));
  ASSERT_TRUE(master.send("hi", 2));
  char buf[8];
  EXPECT_EQ(follower.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), 2);
  close(silent);
}

// the first mapping of the links' shared memory in this process (both ends map it here)
char* link_memory(std::size_t& size) {
  std::ifstream maps("/proc/self/maps");
  for (std::string line; std::getline(maps, line);) {
    if (line.find("memfd:enact-loop-link") == std::string::npos) continue;
    const std::uintptr_t from = std::stoull(line.substr(0, line.find('-')), nullptr, 16);
    const std::uintptr_t to = std::stoull(line.substr(line.find('-') + 1), nullptr, 16);
    size = to - from;
    return reinterpret_cast<char*>(from);
  }
  return nullptr;
}

TEST(LoopLink, ARecordThatRunsPastTheRingsEndEndsTheLinkAndNothingIsReadPastIt) {
  TempDir dir;
  Pair p(dir);
  // the master's records fill the follower's ring up to the last 4096 bytes (records of an
  // 8-byte header and a payload of a multiple of 8), then one leaves 8 bytes at its end
  char out[LoopLink::kMaxMessage] = {}, in[LoopLink::kMaxMessage];
  constexpr std::size_t kRecord = LoopLink::kMaxMessage;
  for (std::size_t i = 0; i + 1 < LoopLink::kRingBytes / kRecord; ++i) {
    ASSERT_TRUE(p.master.send(out, kRecord - 8));
    ASSERT_EQ(p.follower.receive(in, sizeof in, rt::now_ns() + kSecond_ns), static_cast<long>(kRecord - 8));
  }
  const char marker[] = "corrupt me here!";
  std::memcpy(out, marker, 16);
  ASSERT_TRUE(p.master.send(out, kRecord - 16));
  // a peer (or a stray write) makes its size one that runs 8 bytes past the ring's end: still
  // no larger than a message may be
  std::size_t size = 0;
  char* memory = link_memory(size);
  ASSERT_NE(memory, nullptr) << "no link memory in /proc/self/maps";
  char* at = static_cast<char*>(memmem(memory, size, marker, 16));
  ASSERT_NE(at, nullptr);
  const std::uint32_t bad = LoopLink::kMaxMessage;
  std::memcpy(at - 8, &bad, sizeof bad);
  EXPECT_EQ(p.follower.receive(in, sizeof in, rt::now_ns() + kSecond_ns), -1) << "a record past the ring's end was read";
  EXPECT_FALSE(p.follower.connected());
}

TEST(LoopLink, AStoppedFollowerNeverBlocksTheMasterItsMessagesAreDropped) {
  TempDir dir;
  Pair p(dir);
  // the follower reads nothing: its queue fills, then sends are refused at once
  const char state[100] = {};
  int refused = 0;
  for (int i = 0; i < 100'000; ++i) refused += !p.master.send(state, sizeof state);
  EXPECT_GT(refused, 0);
  EXPECT_EQ(p.master.counters().dropped, static_cast<std::uint64_t>(refused));
  EXPECT_EQ(p.master.counters().sent + p.master.counters().dropped, 100'000u);
  EXPECT_TRUE(p.master.connected()) << "a full queue is not a lost peer";
  // what was queued is still there, in order
  char buf[128];
  EXPECT_EQ(p.follower.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns), 100);
}

TEST(LoopLink, SendAndReceiveAllocateNothing) {
  TempDir dir;
  Pair p(dir);
  char buf[128];
  const char state[100] = {};
  test::AllocGuard guard;
  for (int i = 0; i < 1000; ++i) {
    p.master.send(state, sizeof state);
    p.follower.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns);
    p.follower.send(state, 20);
    p.master.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns);
  }
  EXPECT_EQ(guard.allocations(), 0u);
}

// a publisher that also sends over the loop's hop (the FFD driver's ffd/state) sends there
// first and holds the bus copy until the loop has its answer (send_held): the observers' copy
// costs the round trip nothing. No copy is lost: the next publish and the publisher's end
// send one still held, in order. Without a peer on the hop the bus copy goes at once
TEST(LoopLink, APublishersBusCopyWaitsForSendHeldAndNoneIsLost) {
  TempDir dir;
  Pair p(dir);
  BytePublisher bytes(test::bind_endpoint("ipc", dir), {.node = "ffd"});
  ByteSubscriber observer_bytes;
  Subscriber<msgs::DeviceState> observer(observer_bytes, "ffd/state");
  observer_bytes.connect(bytes.endpoint());
  observer_bytes.subscribe("ffd/state");
  ASSERT_TRUE(test::eventually([&] { return bytes.has_subscribers("ffd/state"); }));
  char buf[LoopLink::kMaxMessage];
  msgs::DeviceState state = test::sample_state(0.01), got;
  {
    Publisher<msgs::DeviceState> states(bytes, "ffd/state");
    states.also_over(&p.master);
    ASSERT_TRUE(states.publish(state));
    const long n = p.follower.receive(buf, sizeof buf, rt::now_ns() + kSecond_ns);
    ASSERT_GT(n, 0);
    ASSERT_TRUE(got.ParseFromArray(buf, static_cast<int>(n)));
    EXPECT_EQ(got.header().seq(), 1u);
    EXPECT_FALSE(observer.receive(100)) << "the bus copy went before send_held";
    ASSERT_TRUE(states.send_held());
    auto first = observer.receive(test::kWait_ms);
    ASSERT_TRUE(first);
    EXPECT_EQ(first->header().seq(), 1u);
    EXPECT_TRUE(states.send_held()) << "nothing held: nothing to send";
    ASSERT_TRUE(states.publish(state));  // seq 2, held
    ASSERT_TRUE(states.publish(state));  // sends 2, holds 3
  }  // the publisher's end sends 3
  for (std::uint64_t seq : {2u, 3u}) {
    auto m = observer.receive(test::kWait_ms);
    ASSERT_TRUE(m) << "seq " << seq << " lost";
    EXPECT_EQ(m->header().seq(), seq);
  }
  EXPECT_FALSE(observer.receive(100)) << "a copy was sent twice";
  // a hop without a peer (the simulator not connected yet, or restarting): the bus carries the
  // loop, so its copy goes at once
  LoopLink lonely = LoopLink::listen(loop_link_path(dir.path(), "lonely"));
  Publisher<msgs::DeviceState> alone(bytes, "ffd/state");
  alone.also_over(&lonely);
  ASSERT_TRUE(alone.publish(state));
  EXPECT_TRUE(observer.receive(test::kWait_ms)) << "held although nothing went over the hop";
}

TEST(LoopLink, NobodyListeningLeavesTheFollowerUnconnectedAtItsDeadline) {
  TempDir dir;
  const std::int64_t deadline = rt::now_ns() + 30'000'000;
  const LoopLink link = LoopLink::connect(dir.file("loop.nobody.sock"), deadline);
  EXPECT_FALSE(link.connected());
  EXPECT_GE(rt::now_ns(), deadline);
}

TEST(LoopLink, APathTooLongForAUnixSocketIsRefusedWithTheFix) {
  const std::string dir(120, 'd');
  try {
    loop_link_path("/tmp/" + dir, "ffd");
    FAIL() << "a 130-byte path was accepted";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("too long"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("fix:"), std::string::npos) << e.what();
  }
}

TEST(LoopLink, AStaleSocketFileOfADeadGraphIsReplaced) {
  TempDir dir;
  const std::string path = loop_link_path(dir.path(), "ffd");
  test::write_file(path, "left by a graph killed with -9");
  LoopLink master = LoopLink::listen(path);
  LoopLink follower = LoopLink::connect(path, rt::now_ns() + kSecond_ns);
  EXPECT_TRUE(follower.connected());
}

}  // namespace
}  // namespace enact::bus
