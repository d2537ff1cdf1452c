// Re-synchronising the model with the device after an interruption: on the bridge, a device
// driven 8 mm into the top while the force was cut comes back without a jolt.
#include "core/sim/reengage.h"
#include "core/sim/simulator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

#include "tests/support/alloc_guard.h"
#include "tests/sim/sim_test_util.h"
#include "tests/support/test_util.h"

namespace enact::sim {
namespace {

constexpr std::int64_t kStep_ns = 200'000;  // 5 kHz
// 1 mm into the middle of the first segment's top (tests/sim/sim_test_util.h), and 8 mm deeper
using test_util::kPressed;
const math::Vec3 kDeep{0.0, -0.0148492, 0.003};

Simulator pressed_bridge() {
  Simulator sim;
  SimParams p;
  p.scene = test::source_path("launch/scenes/bridge.yaml");
  sim.configure(p);
  sim.activate(0);
  for (int i = 0; i < 50; ++i) sim.step(i * kStep_ns, kPressed);
  return sim;
}

// steps from `from_ns` for 150 ms at `at`, positions through `reengage` when given: the first
// force (what the force path comes back to) and the last, and the largest change between
// two steps after the first
struct Forces {
  double largest_step_n = 0.0, first_n = 0.0, last_n = 0.0;
};
Forces run(Simulator& sim, std::int64_t from_ns, const math::Vec3& at, Reengagement* reengage) {
  Forces r;
  double previous = 0.0;
  for (int i = 0; i < 750; ++i) {
    const std::int64_t t = from_ns + i * kStep_ns;
    const double f = math::norm(sim.step(t, reengage ? reengage->position(sim, t, at) : at).force_n);
    if (i == 0) r.first_n = f;
    if (i > 0) r.largest_step_n = std::max(r.largest_step_n, std::abs(f - previous));
    previous = f;
  }
  r.last_n = previous;
  return r;
}

TEST(Reengagement, DeepDeviceAfterAnInterruptionComesBackWithoutAJolt) {
  // without: the first step 8 mm deeper answers hundreds of N at once
  Simulator plain = pressed_bridge();
  const double resting_n = math::norm(plain.output().force_n);
  const Forces jolt = run(plain, 50 * kStep_ns, kDeep, nullptr);
  EXPECT_GT(jolt.first_n - resting_n, 100.0);

  // with: the body starts just out of the bridge and returns to the device over 100 ms
  Simulator sim = pressed_bridge();
  Reengagement reengage(0.100);
  reengage.interrupt();
  const Forces gentle = run(sim, 50 * kStep_ns, kDeep, &reengage);
  std::printf("[ measure ] 8 mm deep after an interruption: first force %.1f N at once without re-synchronising; with it %.2f N, then "
              "at most %.2f N per step, %.1f N after 150 ms (offset %.1f mm)\n",
              jolt.first_n, gentle.first_n, gentle.largest_step_n, gentle.last_n, reengage.largest_offset_m() * 1e3);
  EXPECT_LT(gentle.first_n, 1.0);
  EXPECT_NEAR(reengage.largest_offset_m(), 0.009, 0.0015);
  EXPECT_EQ(reengage.count(), 1u);
  // the force grows in steps of at most 1 % of the way, and ends where the model puts it
  EXPECT_LT(gentle.largest_step_n, 0.01 * jolt.last_n);
  EXPECT_NEAR(gentle.last_n, jolt.last_n, 1e-6 * jolt.last_n);
}

TEST(Reengagement, NothingToDoOutOfContactAndNoAllocation) {
  Simulator sim = pressed_bridge();
  const math::Vec3 above{0.0, -0.0148492, 0.030};
  EXPECT_EQ(resync_offset(sim.model(), sim.state(), above), math::Vec3{});
  Reengagement reengage;
  std::size_t allocations = 0;
  {
    test::AllocGuard guard;
    reengage.interrupt();
    for (std::int64_t t = 100 * kStep_ns; t < 110 * kStep_ns; t += kStep_ns) sim.step(t, reengage.position(sim, t, kDeep));
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
}

}  // namespace
}  // namespace enact::sim
