// Live parameter changes are planned off the loop thread (the ParamPort's own thread): a
// computer model from a YAML file is read and checked there, while the loop answers device
// states as enact-sim's does: it opens no file, and applying the prepared change and
// stepping on it allocate nothing.
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

#include "core/bus/bytes.h"
#include "core/bus/typed.h"
#include "core/graph/messages.h"
#include "core/graph/graph_dir.h"
#include "core/params/param_bus.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"
#include "core/sim/simulator.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/file_guard.h"
#include "tests/support/test_util.h"

namespace enact::graph {
namespace {

TEST(ParamPort, AModelFromAYamlFileIsReadOffTheLoopThreadAndAppliedWithoutAllocating) {
  const test::TempDir dir;
  setenv("ENACT_GRAPH_DIR", dir.path().c_str(), 1);
  const std::string model_file = dir.file("edges.yaml");
  test::write_file(model_file, "name: edges\nforce: [0, 3, 12, 15]\npins: contact\n");
  sim::Simulator simulator;
  sim::SimParams p;
  p.scene = test::source_path("launch/scenes/bridge.yaml");
  simulator.configure(p);
  bus::BytePublisher inbound(node_endpoint(kInboundNode), {.node = kInboundNode});
  bus::BytePublisher out(node_endpoint("sim"), {.node = "sim"});
  bus::Publisher<msgs::TaskEvent> events(out, kTaskEvent);
  ParamPort port(simulator, "sim", out, events);
  for (int waited_ms = 0; !inbound.has_subscribers(kParamSet) && waited_ms < 5000; ++waited_ms) rt::sleep_until_ns(rt::now_ns() + 1'000'000);
  ASSERT_TRUE(inbound.has_subscribers(kParamSet));
  msgs::ParamUpdate update;
  update.set_name("sim.model");
  update.set_text(model_file);
  update.set_request_id(7);
  const std::string bytes = update.SerializeAsString();
  const std::size_t opened_before = test::FileGuard::opens_by_any_thread();

  // the loop: a device state every 200 us, answered at once; changes taken between steps
  simulator.activate(0);
  msgs::ForceCommand command;
  fill(command, 0, {}, false);  // its parts are made once, by the first answer
  char answer[256];
  std::size_t loop_opens = 0, answer_allocations = 0;
  bool applied = false;
  std::int64_t t_ns = 0;
  std::uint64_t seq = 0;
  for (const std::int64_t give_up = rt::now_ns() + 5'000'000'000; !applied && rt::now_ns() < give_up;) {
    if (seq == 10) inbound.send(kParamSet, msgs::ParamUpdate::descriptor()->full_name(), bytes.data(), bytes.size());
    const test::FileGuard files;
    const std::optional<sim::ParamChange> change = port.next();
    sim::ParamApplied done;
    {
      const test::AllocGuard allocations;
      if (change) done = simulator.apply(*change, t_ns);
      t_ns += 200'000;
      const sim::StepOutput& o = simulator.step(t_ns, {0.0, 0.0, 0.02});
      fill(command, ++seq, o.force_n, o.fault);
      command.SerializeToArray(answer, sizeof answer);
      answer_allocations += allocations.allocations();
    }
    if (change) port.applied(done);
    port.stepped(simulator.steps(), seq, t_ns);
    applied = change.has_value();
    loop_opens += files.opens();
    rt::sleep_until_ns(rt::now_ns() + 200'000);
  }
  ASSERT_TRUE(applied) << "the model change was not planned in 5 s";
  EXPECT_EQ(simulator.computer_model().name, "edges");
  // the file was read, by another thread than the loop's
  EXPECT_GT(test::FileGuard::opens_by_any_thread(), opened_before);
  EXPECT_EQ(loop_opens, 0u) << "the loop thread opened a file";
  EXPECT_EQ(answer_allocations, 0u) << "the answer path allocated";
}

}  // namespace
}  // namespace enact::graph
