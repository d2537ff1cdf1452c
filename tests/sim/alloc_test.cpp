#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/sim/offline.h"
#include "core/sim/simulator.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/test_util.h"

namespace enact::sim {
namespace {

TEST(AllocGuard, CountsAVectorGrowing) {
  std::vector<int> v;
  std::size_t counted = 0;
  {
    const test::AllocGuard guard;
    v.push_back(1);
    counted = guard.allocations();
  }
  EXPECT_EQ(v.size(), 1u);
  EXPECT_GT(counted, 0u);
}

// 10^4 steps along the scripted path: at 1 kHz the whole trial (contact, both excursions,
// the fall's start and end, completion), at the scene's 5 kHz its first 2 s
void expect_steps_allocate_nothing(double rate_hz) {
  SCOPED_TRACE(rate_hz);
  constexpr int kSteps = 10000;
  SimParams p;
  p.scene = test::source_path("launch/scenes/bridge.yaml");
  p.rate_hz = rate_hz;
  Simulator sim;
  sim.configure(p);
  const task::Trajectory tr = scripted_path(sim);
  std::vector<math::Vec3> positions(kSteps);
  std::vector<std::int64_t> times_ns(kSteps);
  for (int n = 0; n < kSteps; ++n) {
    const double t = n * sim.model().dt_s;
    positions[n] = tr.at(t);
    times_ns[n] = std::llround(t * 1e9);
  }
  sim.activate(0);
  std::size_t allocations = 0;
  int touching_steps = 0;
  {
    const test::AllocGuard guard;
    for (int n = 0; n < kSteps; ++n) touching_steps += sim.step(times_ns[n], positions[n]).contacts > 0;
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(touching_steps, 0);
  EXPECT_LT(touching_steps, kSteps);
  if (rate_hz == 1000.0) {
    EXPECT_EQ(sim.metrics().falls, 1);
    EXPECT_TRUE(sim.metrics().completed);
  }
}

TEST(SimulatorStep, AllocatesNothingAlongTheScriptedPath) {
  expect_steps_allocate_nothing(1000.0);
  expect_steps_allocate_nothing(5000.0);
}

}  // namespace
}  // namespace enact::sim
