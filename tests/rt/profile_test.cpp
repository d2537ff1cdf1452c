// The real-time profile: which CPUs and priorities it plans, what it applies, and how it
// reports refusals, on a scripted system (no real pinning or FIFO is needed to run it).
#include <gtest/gtest.h>

#include <cerrno>
#include <string>
#include <vector>

#include "core/config/yaml.h"
#include "core/rt/profile.h"

namespace {

using namespace enact::rt;

// a system that records every call and refuses what it is told to
struct FakeSystem {
  std::vector<int> cpus = {0, 1};
  int pin_error = 0, fifo_error = 0, latency_error = 0;
  std::vector<std::vector<int>> pinned;
  std::vector<int> fifo_calls;
  int held = 0, released = 0;

  ProfileSystem calls() {
    return {[this] { return cpus; },
            [this](const std::vector<int>& c) {
              pinned.push_back(c);
              return pin_error;
            },
            [this](int p) {
              fifo_calls.push_back(p);
              return p > 0 ? fifo_error : 0;
            },
            [this](int& fd) {
              fd = latency_error ? -1 : 42;
              held += latency_error ? 0 : 1;
              return latency_error;
            },
            [this](int fd) { released += fd == 42 ? 1 : 0; }};
  }
};

bool mentions(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

GraphProfile bridge(int fifo = 0) { return {.enabled = true, .loop = {"ffd", "sim"}, .fifo_priority = fifo, .cpu_latency = true}; }

TEST(RtProfile, TwoCpusPutTheLoopOnTheLastAndTheLauncherOnTheOther) {
  FakeSystem sys;
  {
    const LauncherProfile p(bridge(), sys.calls());
    EXPECT_EQ(p.loop_cpus(), std::vector<int>{1});
    EXPECT_EQ(p.other_cpus(), std::vector<int>{0});
    ASSERT_EQ(sys.pinned.size(), 1u);
    EXPECT_EQ(sys.pinned[0], std::vector<int>{0});  // the launcher, before it starts anything
    EXPECT_TRUE(p.cpu_latency_held());
    EXPECT_EQ(p.node("sim").cpus, std::vector<int>{1});
    EXPECT_EQ(p.node("ffd").cpus, std::vector<int>{1});
    // each knows it shares the CPU with the other: the driver's loop must sleep every tick
    EXPECT_EQ(p.node("ffd").sharing, 2);
    EXPECT_EQ(p.node("sim").sharing, 2);
    EXPECT_TRUE(p.node("logger").cpus.empty());
    EXPECT_FALSE(p.in_loop("tactile"));
    EXPECT_TRUE(sys.fifo_calls.empty());  // no FIFO asked for: none tried
    EXPECT_TRUE(mentions(p.summary(), "CPU 1")) << p.summary();
  }
  EXPECT_EQ(sys.released, 1);  // the latency request ends with the profile
  // and the launcher gets its CPUs back (an experiment's next trial places its loop again)
  ASSERT_EQ(sys.pinned.size(), 2u);
  EXPECT_EQ(sys.pinned[1], (std::vector<int>{0, 1}));
}

// a second graph on the machine (the registry's running loops): its loop goes on a CPU the
// first graph's loop does not hold; with every CPU held, it shares one and says what it costs
TEST(RtProfile, ASecondGraphPlacesItsLoopOnACpuNoOtherLoopHolds) {
  FakeSystem sys;
  sys.cpus = {0, 1, 2, 3};
  GraphProfile second = bridge();
  second.other_loops = {{3, "bridge_rt"}};
  const LauncherProfile p(second, sys.calls());
  EXPECT_EQ(p.loop_cpus(), std::vector<int>{2});
  EXPECT_EQ(p.other_cpus(), (std::vector<int>{0, 1}));  // not beside the other loop either
  EXPECT_TRUE(mentions(p.summary(), "graph 'bridge_rt's loop holds CPU 3: this loop goes on CPU 2")) << p.summary();

  // two CPUs, the last held: the loop takes the first, the rest runs beside the other loop
  FakeSystem two;
  GraphProfile other = bridge();
  other.other_loops = {{1, "bridge_rt"}};
  const LauncherProfile q(other, two.calls());
  EXPECT_EQ(q.loop_cpus(), std::vector<int>{0});
  EXPECT_EQ(q.other_cpus(), std::vector<int>{1});
  EXPECT_TRUE(mentions(q.summary(), "where this graph's other processes run beside it")) << q.summary();

  // every CPU held: shared, said plainly with the fix
  FakeSystem full;
  GraphProfile third = bridge();
  third.other_loops = {{0, "a"}, {1, "b"}};
  const LauncherProfile r(third, full.calls());
  ASSERT_EQ(r.loop_cpus().size(), 1u);
  EXPECT_TRUE(mentions(r.summary(), "every CPU holds a loop already: this loop shares CPU 1 with graph 'b'")) << r.summary();
  EXPECT_TRUE(mentions(r.summary(), "fix: stop the other graph")) << r.summary();
}

TEST(RtProfile, FifoIsOrderedIoThreadsFirstThenTheLoopInItsOrder) {
  FakeSystem sys;
  const LauncherProfile p(bridge(80), sys.calls());
  ASSERT_TRUE(p.fifo_permitted());
  // the loop's hop is the local link, read by the loop threads: their ZeroMQ I/O threads
  // (observers) stay at normal scheduling, off the loop's CPU
  EXPECT_EQ(p.node("ffd").io_fifo_priority, 0);
  EXPECT_EQ(p.node("ffd").fifo_priority, 79);
  EXPECT_EQ(p.node("sim").io_fifo_priority, 0);
  EXPECT_EQ(p.node("sim").fifo_priority, 78);
  EXPECT_EQ(p.node("viewer").fifo_priority, 0);
  // the launcher tried FIFO and went back to normal scheduling
  EXPECT_EQ(sys.fifo_calls, (std::vector<int>{80, 0}));
  // the hop forced onto ZeroMQ (loop_transport=zeromq): the I/O threads carry the loop, first
  GraphProfile zmq_hop = bridge(80);
  zmq_hop.io_with_loop = true;
  const LauncherProfile q(zmq_hop, sys.calls());
  EXPECT_EQ(q.node("ffd").io_fifo_priority, 80);
  EXPECT_EQ(q.node("ffd").fifo_priority, 79);
  EXPECT_EQ(q.node("sim").io_fifo_priority, 80);
  EXPECT_EQ(q.node("sim").fifo_priority, 78);
}

TEST(RtProfile, RefusalsAreSaidOnceAndNothingRefusedReachesTheNodes) {
  FakeSystem sys;
  sys.pin_error = EPERM;
  sys.fifo_error = EPERM;
  sys.latency_error = EACCES;
  const LauncherProfile p(bridge(80), sys.calls());
  EXPECT_FALSE(p.fifo_permitted());
  EXPECT_FALSE(p.cpu_latency_held());
  const std::string s = p.summary();
  EXPECT_TRUE(mentions(s, "pinning to CPU 0 refused")) << s;
  EXPECT_TRUE(mentions(s, "SCHED_FIFO 80 refused")) << s;
  EXPECT_TRUE(mentions(s, "CPU latency request (/dev/cpu_dma_latency) refused")) << s;
  EXPECT_TRUE(mentions(s, "fix:")) << s;
  // the nodes get neither CPUs nor FIFO, so they neither fail nor repeat the refusal
  const NodeProfile sim = p.node("sim");
  EXPECT_TRUE(sim.cpus.empty());
  EXPECT_EQ(sim.fifo_priority, 0);
  EXPECT_EQ(sim.io_fifo_priority, 0);
  EXPECT_EQ(sys.released, 0);
}

TEST(RtProfile, OneCpuPinsNothing) {
  FakeSystem sys;
  sys.cpus = {3};
  const LauncherProfile p(bridge(), sys.calls());
  EXPECT_TRUE(sys.pinned.empty());
  EXPECT_TRUE(p.node("sim").cpus.empty());
  EXPECT_TRUE(mentions(p.summary(), "one CPU (3)")) << p.summary();
}

TEST(RtProfile, OffAppliesNothing) {
  FakeSystem sys;
  GraphProfile g = bridge(80);
  g.enabled = false;
  const LauncherProfile p(g, sys.calls());
  EXPECT_TRUE(sys.pinned.empty());
  EXPECT_TRUE(sys.fifo_calls.empty());
  EXPECT_EQ(sys.held, 0);
  EXPECT_FALSE(p.in_loop("sim"));
  EXPECT_EQ(p.summary(), "real-time profile: off");
}

TEST(RtProfile, PriorityMustLeaveRoomForTheOrder) {
  GraphProfile g = bridge(2);  // I/O 2, ffd 1, sim 0: not a FIFO priority
  EXPECT_THROW(g.validate(), enact::config::Error);
  g.fifo_priority = 3;
  EXPECT_NO_THROW(g.validate());
  g.fifo_priority = 100;
  EXPECT_THROW(g.validate(), enact::config::Error);
}

TEST(RtProfile, NodeProfileRoundTripsThroughTheEnvironment) {
  const NodeProfile p{.cpus = {1, 3}, .fifo_priority = 79, .io_fifo_priority = 80, .sharing = 2};
  const NodeProfile q = NodeProfile::from_env(p.to_env());
  EXPECT_EQ(q.cpus, p.cpus);
  EXPECT_EQ(q.sharing, 2);
  EXPECT_EQ(q.fifo_priority, 79);
  EXPECT_EQ(q.io_fifo_priority, 80);
  EXPECT_TRUE(NodeProfile::from_env(NodeProfile{}.to_env()).cpus.empty());
  for (const char* bad : {"cpus=one", "fifo=120", "speed=3", "cpus=1,-2", "sharing=two"}) {
    EXPECT_THROW(NodeProfile::from_env(bad), enact::config::Error) << bad;
  }
}

TEST(RtProfile, ANodeGivesItsIoThreadsOnlyWhatItWasGranted) {
  const NodeProfile wanted{.cpus = {1}, .fifo_priority = 79, .io_fifo_priority = 80};
  FakeSystem ok;
  const NodeProfileReport granted = apply_node_profile(wanted, ok.calls());
  EXPECT_TRUE(granted.pinned);
  EXPECT_TRUE(granted.fifo);
  EXPECT_EQ(granted.io_cpus, std::vector<int>{1});
  EXPECT_EQ(granted.io_fifo_priority, 80);
  // refused: libzmq would abort its I/O thread on a refused setting, so none is passed on
  FakeSystem no;
  no.pin_error = EINVAL;
  no.fifo_error = EPERM;
  const NodeProfileReport refused = apply_node_profile(wanted, no.calls());
  EXPECT_FALSE(refused.pinned);
  EXPECT_FALSE(refused.fifo);
  EXPECT_TRUE(refused.io_cpus.empty());
  EXPECT_EQ(refused.io_fifo_priority, 0);
  EXPECT_TRUE(mentions(refused.summary(), "refused")) << refused.summary();
}

}  // namespace
