// enact-sim's component as its process host builds it (node::Host, node::Sim), its FFD driver
// the test itself at the other end of the same-host link: the whole answering path of the
// real node, not a copy of its loop
#include <gtest/gtest.h>

#include <csignal>
#include <new>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

#include "core/bus/loop_link.h"
#include "core/bus/typed.h"
#include "core/config/env.h"
#include "core/graph/messages.h"
#include "core/graph/sockets.h"
#include "core/graph/topics.h"
#include "core/node/host.h"
#include "core/node/sim.h"
#include "core/params/params.h"
#include "core/rt/clock.h"
#include "core/rt/rt_section.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/param_update.pb.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/file_guard.h"
#include "tests/support/test_util.h"

namespace enact::node {
namespace {

// the counters count what a real-time section does, on any thread
TEST(SimNode, TheGuardsCountWhatARealTimeSectionDoesOnAnyThread) {
  const std::size_t allocations = test::AllocGuard::in_rt_sections();
  // operator new called as a function: a new-expression's pair the compiler may leave out
  auto allocate = [] { ::operator delete(::operator new(64)); };
  std::thread([&] {
    const rt::RtSection section;
    allocate();
  }).join();
  EXPECT_EQ(test::AllocGuard::in_rt_sections(), allocations + 1);
  allocate();  // outside a section: not counted
  EXPECT_EQ(test::AllocGuard::in_rt_sections(), allocations + 1);
}

TEST(SimNode, AModelChangeFromAYamlFileReachesTheLoopAsPreparedStateItsAnswersAllocateNothingAndReadNoFile) {
  const test::TempDir dir;
  setenv(env::kGraphDir, dir.path().c_str(), 1);
  for (const char* name : {env::kClock, env::kRtProfile, env::kRespawn, env::kReadyFd}) unsetenv(name);
  const std::string model_file = dir.file("edges.yaml");
  test::write_file(model_file, "name: edges\nforce: [0, 3, 12, 15]\npins: contact\n");
  // the FFD driver's end of the link, listening before the simulator looks for it
  bus::LoopLink driver = bus::LoopLink::listen(bus::loop_link_path(dir.path(), "ffd"));

  // the simulator, as host_main builds it
  std::vector<std::string> words = {"enact-sim", "--param", "scene=" + test::source_path("launch/scenes/bridge.yaml")};
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  Host host(kSim, graph::parse_node_args(static_cast<int>(argv.size()), argv.data(), kSim.default_name));
  Sim sim(host);
  host.open();
  sim.open_ports();
  host.announce();
  sim.activate();
  host.ready();
  std::thread feed([&] { sim.run(); });
  ASSERT_TRUE(driver.wait_for_peer(rt::now_ns() + 5'000'000'000)) << "the simulator did not connect to the link";

  // the sender of the request, and its answer
  bus::BytePublisher inbound(graph::node_endpoint(graph::kInboundNode), {.node = graph::kInboundNode});
  bus::ByteSubscriber acks_in;
  bus::Subscriber<msgs::ParamAck> acks(acks_in, graph::kParamAck);
  acks_in.connect(graph::node_endpoint("sim"));
  msgs::ParamUpdate update;
  update.set_name("sim.model");
  update.set_text(model_file);
  update.set_request_id(7);
  const std::string request = update.SerializeAsString();

  // the driver's loop: a state every 200 us, its answer awaited before the next
  msgs::DeviceState state;
  graph::fill(state, devices::ForceSample{});
  state.mutable_header()->set_source("ffd");
  msgs::ForceCommand answer;
  char bytes[bus::LoopLink::kMaxMessage];
  constexpr std::uint64_t kWarmUp = 20;  // the first answers make their messages' parts, once
  std::size_t allocations_before = 0, opens_before = 0, opens_any_before = 0;
  std::uint64_t unanswered = 0, mismatched = 0, sent_request_at = 0, applied_at = 0;
  msgs::ParamAck ack;
  bool acked = false;
  const std::int64_t t0 = rt::now_ns();
  std::uint64_t seq = 0;
  for (const std::int64_t give_up = t0 + 10'000'000'000; rt::now_ns() < give_up && (!acked || seq < applied_at + 500);) {
    ++seq;
    if (seq == kWarmUp) {
      allocations_before = test::AllocGuard::in_rt_sections();
      opens_before = test::FileGuard::opens_in_rt_sections();
      opens_any_before = test::FileGuard::opens_by_any_thread();
    }
    if (seq >= kWarmUp + 50 && inbound.has_subscribers(graph::kParamSet) && !acked && (sent_request_at == 0 || seq - sent_request_at > 2500)) {
      inbound.send(graph::kParamSet, msgs::ParamUpdate::descriptor()->full_name(), request.data(), request.size());
      sent_request_at = seq;
    }
    const std::int64_t t = t0 + static_cast<std::int64_t>(seq) * 200'000;
    state.mutable_header()->set_seq(seq);
    state.mutable_header()->set_stamp_ns(t);
    graph::set(*state.mutable_position(), {0.0, 0.0, 0.02 - 1e-6 * static_cast<double>(seq % 1000)});
    const std::size_t size = state.ByteSizeLong();
    state.SerializeToArray(bytes, static_cast<int>(size));
    ASSERT_TRUE(driver.send(bytes, size));
    const long n = driver.receive(bytes, sizeof bytes, rt::now_ns() + 1'000'000'000);
    if (n <= 0) {
      ++unanswered;
    } else if (!answer.ParseFromArray(bytes, static_cast<int>(n)) || answer.answered_seq() != seq) {
      ++mismatched;
    }
    if (!acked && acks.receive(ack, 0) && ack.request_id() == 7) {
      acked = true;
      applied_at = seq;
    }
    rt::sleep_until_ns(rt::now_ns() + 200'000);
  }
  std::raise(SIGTERM);  // the host's stop handler: the node ends as on Ctrl-C
  feed.join();
  alarm(0);  // the stop's grace period is not needed
  EXPECT_EQ(sim.deactivate(), 0);

  ASSERT_TRUE(acked) << "the model change was not answered in 10 s";
  EXPECT_TRUE(ack.applied()) << ack.reason();
  EXPECT_GT(ack.state_seq(), sent_request_at) << "applied from a step after the request";
  EXPECT_EQ(unanswered, 0u);
  EXPECT_EQ(mismatched, 0u);
  // the model's file was read, and not by the loop
  EXPECT_GT(test::FileGuard::opens_by_any_thread(), opens_any_before);
  EXPECT_EQ(test::FileGuard::opens_in_rt_sections(), opens_before) << "the answering path opened a file";
  EXPECT_EQ(test::AllocGuard::in_rt_sections(), allocations_before) << "the answering path allocated";
  std::printf("%llu states answered; the model change applied from state %llu, acked by state %llu\n", static_cast<unsigned long long>(seq),
              static_cast<unsigned long long>(ack.state_seq()), static_cast<unsigned long long>(applied_at));
}

}  // namespace
}  // namespace enact::node
