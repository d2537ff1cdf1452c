#include "core/sim/keyframe.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/sim/offline.h"
#include "core/sim/simulator.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/test_util.h"

namespace enact::sim {
namespace {

SimParams bridge_at(double rate_hz) {
  SimParams p;
  p.scene = test::source_path("launch/scenes/bridge.yaml");
  p.rate_hz = rate_hz;
  return p;
}

bool same_bits(const math::Vec3& a, const math::Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// the scripted path at 1 kHz: positions and times of every step of the trial
struct Path {
  std::vector<math::Vec3> at;
  std::vector<std::int64_t> ns;
};

Path path_of(const Simulator& sim) {
  const task::Trajectory tr = scripted_path(sim);
  Path p;
  for (std::int64_t n = 0; n * sim.model().dt_s <= tr.end_s(); ++n) {
    const double t = static_cast<double>(n) * sim.model().dt_s;
    p.at.push_back(tr.at(t));
    p.ns.push_back(std::llround(t * 1e9));
  }
  return p;
}

ParamChange change(const Simulator& sim, const std::string& name, double value) {
  ParamPlanner planner(sim);
  const ParamPlan plan = planner.plan(name, {value, {}, {}}, 1);
  EXPECT_TRUE(plan.accepted) << plan.reason;
  return plan.change;
}

// a simulator run along the scripted path, live changes made before the keyframe (one still
// blending in when it is taken), saved and packed at `keyframe_step`; a fresh simulator
// restored from those bytes steps the rest of the trial as the first does, bit for bit
TEST(Keyframe, ARestoredSimulatorContinuesBitForBit) {
  Simulator live;
  live.configure(bridge_at(1000.0));
  const Path path = path_of(live);
  ASSERT_GT(path.at.size(), 6000u);
  const std::size_t keyframe_step = 3000;
  live.activate(0);
  for (std::size_t n = 0; n < keyframe_step; ++n) {
    if (n == 1000) live.apply(change(live, "stiffness_n_per_m", 3000.0), 0);
    if (n == keyframe_step - 10) live.apply(change(live, "damping_n_s_per_m", 0.01), 0);  // its 50 ms ramp is still on
    live.step(path.ns[n], path.at[n]);
  }
  ASSERT_GT(live.output().contacts, 0) << "the keyframe should be taken while the body touches the bridge";
  Keyframe saved;
  live.save(saved);
  std::string bytes;
  pack(saved, bytes);

  Simulator restored;
  restored.configure(bridge_at(1000.0));
  Keyframe k;
  restored.save(k);
  ASSERT_TRUE(unpack(bytes, k));
  restored.restore(k);
  EXPECT_EQ(restored.steps(), live.steps());
  Simulator fresh;  // the same steps without the keyframe: the test can tell them apart
  fresh.configure(bridge_at(1000.0));
  fresh.activate(0);
  std::size_t fresh_differs = 0;
  for (std::size_t n = keyframe_step; n < path.at.size(); ++n) {
    const StepOutput a = live.step(path.ns[n], path.at[n]);
    const StepOutput& b = restored.step(path.ns[n], path.at[n]);
    ASSERT_TRUE(same_bits(a.force_n, b.force_n)) << "step " << n;
    ASSERT_EQ(a.pins, b.pins) << "step " << n;
    ASSERT_EQ(a.frame_due, b.frame_due) << "step " << n;
    ASSERT_EQ(a.event.kind, b.event.kind) << "step " << n;
    fresh_differs += !same_bits(a.force_n, fresh.step(path.ns[n], path.at[n]).force_n);
  }
  EXPECT_GT(fresh_differs, 0u);
  EXPECT_EQ(live.metrics().falls, restored.metrics().falls);
  EXPECT_EQ(live.metrics().time_out_s, restored.metrics().time_out_s);
  EXPECT_EQ(live.metrics().time_total_s, restored.metrics().time_total_s);
  EXPECT_TRUE(restored.metrics().completed);
}

TEST(Keyframe, SavingAllocatesNothingOnceSized) {
  Simulator sim;
  sim.configure(bridge_at(5000.0));
  sim.activate(0);
  Keyframe k;
  sim.save(k);  // sizes it
  sim.step(0, {0.0, -0.0148492, 0.011});
  std::size_t allocations = 0;
  {
    const test::AllocGuard guard;
    sim.save(k);
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(k.step, 1u);
}

TEST(Keyframe, BytesOfAnotherSceneOrCutShortOrLongAreRefused) {
  Simulator a;
  a.configure(bridge_at(1000.0));
  a.activate(0);
  Keyframe ka;
  a.save(ka);
  std::string bytes;
  pack(ka, bytes);
  Keyframe same;
  a.save(same);
  EXPECT_TRUE(unpack(bytes, same));
  EXPECT_FALSE(unpack(bytes.substr(0, bytes.size() - 1), same));
  EXPECT_FALSE(unpack(bytes + "x", same));
  // a scene with one contact pair fewer: not its keyframe
  same.state.contacts.pop_back();
  EXPECT_FALSE(unpack(bytes, same));
}

}  // namespace
}  // namespace enact::sim
