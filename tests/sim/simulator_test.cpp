#include "core/sim/simulator.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/config/yaml.h"
#include "tests/sim/sim_test_util.h"
#include "tests/support/refusal.h"
#include "tests/support/test_util.h"

namespace enact::sim {
namespace {

using test_util::bridge;
using test_util::kPressed;

constexpr std::uint32_t kPressedPins = 0xffffu & ~((1u << 0) | (1u << 15));

TEST(Simulator, StepBeforeActivateGivesZeroForce) {
  Simulator sim;
  EXPECT_EQ(sim.lifecycle(), Lifecycle::unconfigured);
  EXPECT_EQ(sim.step(0, kPressed).force_n.z, 0.0);
  sim.configure(bridge());
  EXPECT_EQ(sim.lifecycle(), Lifecycle::inactive);
  const StepOutput& out = sim.step(0, kPressed);
  EXPECT_EQ(out.force_n.x, 0.0);
  EXPECT_EQ(out.force_n.y, 0.0);
  EXPECT_EQ(out.force_n.z, 0.0);
  EXPECT_EQ(out.contacts, 0);
  EXPECT_EQ(sim.state().steps, 0);  // nothing was stepped
}

TEST(Simulator, ActiveStepPushesUpAndDeactivateStopsIt) {
  Simulator sim;
  sim.configure(bridge());
  sim.activate(0);
  EXPECT_EQ(sim.lifecycle(), Lifecycle::active);
  const StepOutput& out = sim.step(0, kPressed);
  EXPECT_GT(out.force_n.z, 0.0);
  EXPECT_EQ(out.contacts, 14);
  EXPECT_EQ(out.pins, kPressedPins);
  EXPECT_TRUE(out.on_top);
  sim.deactivate();
  EXPECT_EQ(sim.lifecycle(), Lifecycle::inactive);
  EXPECT_EQ(sim.output().force_n.z, 0.0);
  EXPECT_EQ(sim.step(200000, kPressed).force_n.z, 0.0);
}

TEST(Simulator, ActivateBeforeConfigureIsALogicError) {
  Simulator sim;
  EXPECT_THROW(sim.activate(0), std::logic_error);
}

TEST(Simulator, MissingSceneThrowsNamingTheFile) {
  const test::TempDir dir;
  SimParams p = bridge();
  p.scene = dir.file("no-such-scene.yaml");
  Simulator sim;
  try {
    sim.configure(p);
    FAIL() << "configure accepted a missing scene";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find(p.scene), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("fix:"), std::string::npos) << e.what();
  }
  EXPECT_EQ(sim.lifecycle(), Lifecycle::unconfigured);
}

TEST(Simulator, UnknownComputerModelThrows) {
  Simulator sim;
  EXPECT_THROW(sim.configure(bridge("CM7")), config::Error);
}

TEST(Simulator, SetComputerModelChangesTheForceBetweenSteps) {
  Simulator sim;
  sim.configure(bridge("CM1"));
  sim.activate(0);
  EXPECT_GT(sim.step(0, kPressed).force_n.z, 0.0);
  sim.set_computer_model(*haptics::preset("T"));
  const StepOutput& out = sim.step(200000, kPressed);
  EXPECT_EQ(out.force_n.z, 0.0);
  EXPECT_EQ(out.pins, kPressedPins);
}

// the summary line counts falls and progress only where the scene has a task to count them
TEST(Simulator, SummaryHasTaskMetricsOnlyForASceneWithATask) {
  Simulator with_task;
  with_task.configure(bridge());
  with_task.activate(0);
  with_task.step_sample(0, kPressed, false);
  EXPECT_NE(with_task.summary().find("task: falls 0, progress"), std::string::npos) << with_task.summary();
  EXPECT_NE(with_task.summary().find("re-synchronised with the device 1 time"), std::string::npos) << with_task.summary();

  SimParams p = bridge();
  p.scene = test::source_path("launch/scenes/two_boxes.yaml");
  Simulator no_task;
  no_task.configure(p);
  ASSERT_FALSE(no_task.has_task());
  no_task.activate(0);
  no_task.step_sample(0, {-0.012, 0.003, 0.0115}, false);
  const std::string line = no_task.summary();
  EXPECT_EQ(line.find("task"), std::string::npos) << line;
  EXPECT_EQ(line.find("falls"), std::string::npos) << line;
  EXPECT_EQ(line.find("progress"), std::string::npos) << line;
  EXPECT_NE(line.find("re-synchronised with the device 1 time"), std::string::npos) << line;
}

}  // namespace
}  // namespace enact::sim

namespace enact::sim {
namespace {

// a live number given at start (sim.stiffness_n_per_m=..., a sweep's grid) is the simulator's
// from its first step, as the planner and the parameter board read it; out of its range, or
// past what keeps the loop stable, it is refused with the fix, as a scene file would be
TEST(Simulator, ALiveNumberGivenAtStartHoldsFromTheFirstStep) {
  const LiveNumber& stiffness = *find_live_number("stiffness_n_per_m");
  const std::size_t row = static_cast<std::size_t>(&stiffness - live_numbers().data());
  Simulator loaded;
  loaded.configure(bridge());
  const double scene_n_per_m = stiffness.get(loaded.model(), loaded.computer_model(), loaded.params());
  SimParams p = bridge();
  p.live_at_start[row] = scene_n_per_m / 4.0;
  Simulator softer;
  softer.configure(p);
  EXPECT_DOUBLE_EQ(ParamPlanner(softer).value(stiffness), scene_n_per_m / 4.0);
  EXPECT_DOUBLE_EQ(ParamPlanner(loaded).value(stiffness), scene_n_per_m);
  // the same press into the bridge's top: a quarter of the stiffness, less force
  loaded.activate();
  softer.activate();
  const math::Vec3 pressed{0.0, -0.0148492, 0.011};
  double f_loaded = 0.0, f_softer = 0.0;
  for (int n = 0; n < 2000; ++n) {
    f_loaded = math::norm(loaded.step_sample(n * 200'000, pressed, false).force_n);
    f_softer = math::norm(softer.step_sample(n * 200'000, pressed, false).force_n);
  }
  EXPECT_GT(f_loaded, 0.5);
  EXPECT_LT(f_softer, 0.5 * f_loaded);

  p.live_at_start[row] = -5.0;
  std::string e = test::error_of([&] { Simulator().configure(p); });
  EXPECT_NE(e.find("stiffness_n_per_m"), std::string::npos) << e;
  EXPECT_NE(e.find(">= 0"), std::string::npos) << e;
  EXPECT_NE(e.find("fix:"), std::string::npos) << e;
  p.live_at_start[row] = 1e12;
  e = test::error_of([&] { Simulator().configure(p); });
  EXPECT_NE(e.find("passivity"), std::string::npos) << e;
  EXPECT_NE(e.find("fix:"), std::string::npos) << e;
}

}  // namespace
}  // namespace enact::sim
