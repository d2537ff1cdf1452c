// The command line's parameter client: a request sent before its connection to the attach
// point is up is lost; the client sends it again soon (10 ms, then twice as long each time),
// not a quarter of a second later. Time is given to the client (tick), so nothing is timed.
#include <gtest/gtest.h>

#include <cstdint>

#include "core/bus/attach.h"
#include "core/bus/endpoints.h"
#include "core/bus/typed.h"
#include "core/params/param_bus.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"
#include "msgs/param_update.pb.h"
#include "tests/support/test_util.h"

namespace enact::graph {
namespace {

constexpr std::int64_t kMs = 1'000'000;

TEST(ParamClient, ARequestLostBeforeTheConnectionIsSentAgainWithin10ms) {
  test::TempDir dir;
  const std::string inbound = bus::ipc_endpoint(dir.path(), "attach:in");
  bus::AttachPoint attach("param-client-test", {.inbound_endpoint = inbound, .inbound_topics = {std::string(kParamSet)}});
  ParamClient client(attach.endpoint(), "cli");
  msgs::ParamUpdate update;
  update.set_name("sim.stiffness_n_per_m");
  update.set_number(2500.0);
  // sent while no node listens: the attach point passes it to nobody, lost for certain
  const std::uint64_t id = client.send(update);
  const std::int64_t t0 = rt::now_ns();

  // the node comes, and is known to be connected once another sender's probe reaches it
  bus::ByteSubscriber node_bytes;
  bus::Subscriber<msgs::ParamUpdate> node(node_bytes, std::string(kParamSet));
  node_bytes.connect(inbound);
  bus::AttachSender probe_sender(attach.endpoint(), "probe");
  msgs::ParamUpdate probe, got;
  probe.set_name("probe");
  ASSERT_TRUE(test::eventually([&] {
    probe_sender.send(std::string(kParamSet), probe);
    return node.receive(got, 20) && got.name() == "probe";
  }));
  while (node.receive(got, 50)) {
  }

  // the client's clock: 5 ms after the first send, nothing yet; at 10 ms, the request again
  EXPECT_TRUE(client.tick(t0 + 5 * kMs).empty());
  EXPECT_FALSE(node.receive(got, 100)) << "sent again before 10 ms";
  EXPECT_TRUE(client.tick(t0 + 10 * kMs).empty());
  ASSERT_TRUE(node.receive(got, 2000)) << "not sent again at 10 ms";
  EXPECT_EQ(got.request_id(), id);
  EXPECT_EQ(got.name(), "sim.stiffness_n_per_m");
  // then 20 ms later (not 10), then 40 ms later
  client.tick(t0 + 20 * kMs);
  EXPECT_FALSE(node.receive(got, 100)) << "sent again 10 ms after the first resend";
  client.tick(t0 + 30 * kMs);
  ASSERT_TRUE(node.receive(got, 2000)) << "not sent again 20 ms after the first resend";
  client.tick(t0 + 60 * kMs);
  EXPECT_FALSE(node.receive(got, 100));
  client.tick(t0 + 70 * kMs);
  ASSERT_TRUE(node.receive(got, 2000));
  // never given up before 5 s; given up, unanswered, at 5 s
  EXPECT_TRUE(client.tick(t0 + 4900 * kMs).empty());
  const auto given_up = client.tick(t0 + 5000 * kMs);
  ASSERT_EQ(given_up.size(), 1u);
  EXPECT_EQ(given_up[0].request_id, id);
  EXPECT_FALSE(given_up[0].answered);
}

}  // namespace
}  // namespace enact::graph
