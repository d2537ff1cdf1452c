// The co-located real-time tick: one thread reads the device, steps the model, writes the
// force and the pins in the same tick, and allocates nothing doing it.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "core/devices/device_profile.h"
#include "core/sim/params.h"
#include "tests/graph/colocated_rig.h"
#include "tests/support/alloc_guard.h"

namespace enact::graph {
namespace {

using rig::kPeriod_ns;
using rig::Rig;

TEST(Colocated, ForceIsWrittenInTheSameTickAsTheSample) {
  Rig rig("CM1");
  int on_top = 0;
  for (std::int64_t n = 0; n < 10'000; ++n) {
    const Observation& o = rig.tick(n);
    // the device applies exactly the force the model computed from this tick's sample
    EXPECT_EQ(rig.device->applied_force_n(), o.step.force_n) << "tick " << n;
    EXPECT_EQ(o.force_ns - o.sample.time_ns, 1000);
    EXPECT_EQ(o.seq, static_cast<std::uint64_t>(n + 1));
    on_top += o.step.on_top;
    if (o.step.on_top) {
      EXPECT_GT(o.step.force_n.z, 0.0) << "on the top the bridge pushes up, tick " << n;
    }
    if (o.step.contacts == 0) {
      EXPECT_EQ(math::norm(o.step.force_n), 0.0) << "in the air no force, tick " << n;
    }
  }
  EXPECT_GT(on_top, 1000) << "the hand path reaches the top";
}

TEST(Colocated, PinsFollowTheComputerModelAtTheFrameRate) {
  Rig cm1("CM1"), cm3("CM3");
  int frames = 0;
  for (std::int64_t n = 0; n < 10'000; ++n) {
    const Observation& a = cm1.tick(n);
    const Observation& b = cm3.tick(n);
    // same device path, same contacts: CM3 shows the complement of CM1 on every pin
    ASSERT_EQ(a.step.contacts, b.step.contacts);
    EXPECT_EQ(a.step.pins ^ b.step.pins, 0xffffu) << "tick " << n;
    if (!a.step.frame_due) continue;
    ++frames;
    // the cells were given this frame's pins in this tick
    EXPECT_EQ(cm1.tactile.targets(), a.step.frame);
  }
  // one frame per 24 ms (120 ticks at 5 kHz), the first at tick 0
  EXPECT_EQ(frames, (10'000 + 119) / 120);
}

// the tactile device is optional: without one every tick's force and frame are the same
// (the scripted hand feels no pins), the frames are written nowhere, and nothing allocates
TEST(Colocated, WithoutATactileDeviceEveryTickIsTheSame) {
  Rig with("CM1"), without("CM1", false);
  int frames = 0, raised = 0;
  std::size_t allocations = 0;
  for (std::int64_t n = 0; n < 10'000; ++n) {
    const Observation& a = with.tick(n);
    std::optional<test::AllocGuard> guard;
    if (n >= 100) guard.emplace();  // past first-use set-up
    const Observation& b = without.tick(n);
    if (guard) allocations += guard->allocations();
    guard.reset();
    ASSERT_EQ(a.step.force_n, b.step.force_n) << "tick " << n;
    ASSERT_EQ(a.step.frame_due, b.step.frame_due) << "tick " << n;
    if (!b.step.frame_due) continue;
    ++frames;
    raised += b.step.frame != 0;
    EXPECT_EQ(b.step.frame, a.step.frame) << "tick " << n;
    EXPECT_EQ(with.tactile.targets(), a.step.frame) << "the display was given the frame, tick " << n;
    EXPECT_EQ(without.tactile.targets(), 0u) << "the rig's cells, not given to the loop, are never written, tick " << n;
  }
  EXPECT_GT(raised, 10) << "frames with pins up: the last check is not vacuous (of " << frames << " frames)";
  EXPECT_EQ(allocations, 0u);
}

// a stage that scales the force, adds to it and inverts the frame, and says what it saw and
// what the stages before it left
struct TestStage final : node::LoopComponent {
  double scale = 1.0;
  math::Vec3 add;
  bool invert_frame = false;
  int activated = 0, deactivated = 0, steps = 0;
  node::Tick last;
  devices::ForceSample sample;
  math::Vec3 force_in_n;
  std::uint32_t frame_in = 0;
  void activate() override { ++activated; }
  void step(node::Tick& t) noexcept override {
    ++steps;
    last = t;
    sample = *t.sample;
    force_in_n = t.step->force_n;
    frame_in = t.step->frame;
    t.step->force_n = t.step->force_n * scale + add;
    if (invert_frame) t.step->frame = ~t.step->frame & 0xffffu;
  }
  void deactivate() noexcept override { ++deactivated; }
};

// the stages step in their order after the model and before the force's write: the first
// sees the model's force, the device is given what the last one left (x0.5 then +0.01 N,
// not (f + 0.01 N) x0.5), the cells the frame it left; each sees this tick's sample and times;
// observers see the force written; a tick with stages allocates nothing
TEST(ColocatedStages, StepInOrderBetweenTheModelAndTheWritesWithoutAllocating) {
  TestStage spy, twice, plus, invert;
  twice.scale = 0.5;  // a small change: the hand still walks onto the bridge
  plus.add = {0.0, 0.0, 0.01};
  invert.invert_frame = true;
  Rig rig("CM1", true, {&spy, &twice, &plus, &invert});
  EXPECT_EQ(spy.activated + twice.activated + plus.activated + invert.activated, 4) << "activated with the loop, before any tick";
  EXPECT_EQ(twice.steps, 0);
  int touching = 0, frames = 0;
  std::size_t allocations = 0;
  for (std::int64_t n = 0; n < 5'000; ++n) {
    std::optional<test::AllocGuard> guard;
    if (n >= 100) guard.emplace();  // past first-use set-up
    const Observation& o = rig.tick(n);
    if (guard) allocations += guard->allocations();
    guard.reset();
    const math::Vec3 model_n = spy.force_in_n;
    ASSERT_EQ(twice.force_in_n, model_n) << "tick " << n;
    ASSERT_EQ(plus.force_in_n, model_n * 0.5) << "tick " << n;
    const math::Vec3 expected = model_n * 0.5 + math::Vec3{0.0, 0.0, 0.01};
    ASSERT_EQ(rig.device->applied_force_n(), expected) << "tick " << n;
    ASSERT_EQ(o.step.force_n, expected) << "observers see the force written, tick " << n;
    EXPECT_EQ(plus.last.time_ns, n * kPeriod_ns);
    EXPECT_EQ(plus.last.model_time_ns, n * kPeriod_ns);
    EXPECT_EQ(plus.sample.position_m, o.sample.position_m);
    EXPECT_EQ(plus.sample.time_ns, o.sample.time_ns);
    touching += math::norm(model_n) > 0.1;
    if (o.step.frame_due) {
      frames += spy.frame_in != 0;
      EXPECT_EQ(rig.tactile.targets(), ~spy.frame_in & 0xffffu) << "the cells get the frame the stages left, tick " << n;
    }
  }
  EXPECT_GT(touching, 500) << "ticks where the model pushes: the order check is not vacuous";
  EXPECT_GT(frames, 5) << "frames with pins up: the frame check is not vacuous";
  EXPECT_EQ(twice.steps, 5'000);
  EXPECT_EQ(allocations, 0u);
  rig.loop->deactivate();
  EXPECT_EQ(spy.deactivated + twice.deactivated + plus.deactivated + invert.deactivated, 4);
  EXPECT_EQ(rig.device->applied_force_n(), math::Vec3{}) << "the force is zeroed however the stages left it";
}

// a stage cannot jolt the hand: the safety layer after the stages holds the force to the
// profile's peak and each step to its slew limit, and a NaN a stage makes reaches the device
// as no force
TEST(ColocatedStages, TheSafetyLayerStillLimitsWhatAStageWrites) {
  TestStage huge, nan;
  huge.add = {0.0, 0.0, 1e6};
  Rig big("CM1", true, {&huge});
  const double peak_n = big.force->profile().peak_force_n;
  const double step_n = big.force->profile().max_force_step_n_per_ms * static_cast<double>(kPeriod_ns) * 1e-6;  // N/ms x ms
  ASSERT_GT(peak_n, 0.0);
  ASSERT_GT(step_n, 0.0);
  math::Vec3 before;
  for (std::int64_t n = 0; n < 1'000; ++n) {
    big.tick(n);
    const math::Vec3 now = big.device->applied_force_n();
    ASSERT_LE(math::norm(now), peak_n + 1e-9) << "tick " << n;
    // the first write follows a silence: one millisecond's worth (core/devices/safety.h)
    const double allowed_n = n == 0 ? big.force->profile().max_force_step_n_per_ms : step_n;
    ASSERT_LE(math::norm(now - before), allowed_n + 1e-9) << "tick " << n;
    before = now;
  }
  EXPECT_GT(math::norm(big.device->applied_force_n()), 0.5 * peak_n) << "the stage's push reaches the device, limited";
  nan.scale = std::nan("");
  Rig bad("CM1", true, {&nan});
  for (std::int64_t n = 0; n < 100; ++n) {
    bad.tick(n);
    ASSERT_TRUE(std::isfinite(math::norm(bad.device->applied_force_n()))) << "tick " << n;
  }
}

TEST(Colocated, TickAllocatesNothing) {
  Rig rig("CM1");
  for (std::int64_t n = 0; n < 100; ++n) rig.tick(n);  // past first-use set-up
  std::size_t allocations = 0;
  {
    test::AllocGuard guard;
    for (std::int64_t n = 100; n < 20'000; ++n) rig.tick(n);
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  // the guard counts (the test is not vacuous)
  test::AllocGuard guard;
  std::vector<int> v;
  v.push_back(1);
  EXPECT_GT(guard.allocations(), 0u);
}

TEST(Colocated, QueuedParamChangesApplyAtTheTopOfATickWithoutAllocating) {
  Rig rig("CM1");
  ParamQueue changes;
  AppliedQueue applied;
  rig.loop->connect_params(changes, applied);
  // planned off the loop, as enact-rt's publisher thread does
  sim::ParamPlanner planner(rig.simulator);
  const sim::ParamPlan cm3 = planner.plan("model", {std::nullopt, "CM3", std::nullopt}, 1);
  const sim::ParamPlan stop = planner.plan("trial", {std::nullopt, "stop", std::nullopt}, 2);
  ASSERT_TRUE(cm3.accepted && stop.accepted);
  std::int64_t n = 0;
  while (n < 20'000 && rig.tick(n).step.contacts == 0) ++n;
  ASSERT_LT(n, 20'000) << "the hand never touched";
  std::size_t allocations = 0;
  std::uint32_t pins = 0, contacts = 0;
  {
    test::AllocGuard guard;
    ASSERT_TRUE(changes.try_push(cm3.change));
    ASSERT_TRUE(changes.try_push(stop.change));
    const Observation& o = rig.tick(++n);
    pins = o.step.pins;
    contacts = static_cast<std::uint32_t>(o.step.contacts);
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  // this tick's pins already follow CM3: down where a mass touches
  EXPECT_EQ(static_cast<std::uint32_t>(__builtin_popcount(pins)), 16u - contacts);
  EXPECT_EQ(rig.simulator.computer_model().name, "CM3");
  EXPECT_FALSE(rig.simulator.trial_running());
  sim::ParamApplied a;
  ASSERT_TRUE(applied.try_pop(a));
  EXPECT_EQ(a.request_id, 1u);
  EXPECT_EQ(a.time_ns, n * kPeriod_ns);
  ASSERT_TRUE(applied.try_pop(a));
  EXPECT_EQ(a.kind, sim::ParamKind::trial_stop);
  EXPECT_FALSE(applied.try_pop(a));
}

TEST(Colocated, DeactivateZeroesTheForceAndLowersThePins) {
  Rig rig("CM1");
  std::int64_t n = 0;
  while (n < 20'000 && (rig.tick(n).step.contacts == 0 || math::norm(rig.device->applied_force_n()) == 0.0)) ++n;
  ASSERT_LT(n, 20'000) << "the hand never touched";
  rig.loop->deactivate();
  EXPECT_EQ(rig.device->applied_force_n(), math::Vec3{});
  EXPECT_EQ(rig.tactile.targets(), 0u);
}

}  // namespace
}  // namespace enact::graph
