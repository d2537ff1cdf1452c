// The simulated pin array: linear strokes of rise_time_s, reversal from the level reached,
// deactivate lowering every pin, the 32-pin limit.
#include "core/devices/simulated_tactile.h"

#include <gtest/gtest.h>

#include <array>
#include <string>

#include "core/config/yaml.h"
#include "tests/support/test_util.h"

namespace enact::devices {
namespace {

using test::kMs;
constexpr std::int64_t kT = 1'000 * kMs;  // an arbitrary start time

SimulatedTactileDevice started(SimulatedTactileParams p = {}) {
  SimulatedTactileDevice d(p);
  d.configure();
  d.activate();
  return d;
}

std::array<float, 32> shown(SimulatedTactileDevice& d, std::int64_t now_ns) {
  std::array<float, 32> levels{};
  d.shown(now_ns, levels.data(), static_cast<int>(levels.size()));
  return levels;
}

TEST(SimulatedTactile, RaisingAndLoweringAreLinearOverTheRiseTime) {
  SimulatedTactileDevice d = started();
  d.write(kT, 1u << 5);
  EXPECT_FLOAT_EQ(shown(d, kT)[5], 0.0f);
  EXPECT_FLOAT_EQ(shown(d, kT + 6 * kMs)[5], 0.25f);
  EXPECT_FLOAT_EQ(shown(d, kT + 12 * kMs)[5], 0.5f);
  EXPECT_FLOAT_EQ(shown(d, kT + 24 * kMs)[5], 1.0f);
  EXPECT_FLOAT_EQ(shown(d, kT + 40 * kMs)[5], 1.0f);
  // the others stay down
  const auto levels = shown(d, kT + 40 * kMs);
  for (int i = 0; i < 16; ++i) {
    if (i != 5) {
      EXPECT_FLOAT_EQ(levels[i], 0.0f) << i;
    }
  }
  // lowering is symmetric
  const std::int64_t t2 = kT + 50 * kMs;
  d.write(t2, 0);
  EXPECT_FLOAT_EQ(shown(d, t2)[5], 1.0f);
  EXPECT_FLOAT_EQ(shown(d, t2 + 12 * kMs)[5], 0.5f);
  EXPECT_FLOAT_EQ(shown(d, t2 + 24 * kMs)[5], 0.0f);
  EXPECT_FLOAT_EQ(shown(d, t2 + 30 * kMs)[5], 0.0f);
}

TEST(SimulatedTactile, RewritingTheSameTargetDoesNotRestartTheStroke) {
  SimulatedTactileDevice d = started();
  for (std::int64_t t = kT; t <= kT + 12 * kMs; t += kMs) d.write(t, 1u);
  EXPECT_FLOAT_EQ(shown(d, kT + 12 * kMs)[0], 0.5f);
}

TEST(SimulatedTactile, ReversalMidStrokeContinuesFromTheCurrentLevel) {
  SimulatedTactileDevice d = started();
  d.write(kT, 1u);
  d.write(kT + 6 * kMs, 0u);  // at 0.25
  EXPECT_FLOAT_EQ(shown(d, kT + 6 * kMs)[0], 0.25f);
  EXPECT_FLOAT_EQ(shown(d, kT + 9 * kMs)[0], 0.125f);
  EXPECT_FLOAT_EQ(shown(d, kT + 12 * kMs)[0], 0.0f);
  // and up again from part-way down
  d.write(kT + 20 * kMs, 1u);
  d.write(kT + 32 * kMs, 0u);  // at 0.5
  d.write(kT + 38 * kMs, 1u);  // at 0.25
  EXPECT_FLOAT_EQ(shown(d, kT + 44 * kMs)[0], 0.5f);
  EXPECT_FLOAT_EQ(shown(d, kT + 56 * kMs)[0], 1.0f);
}

TEST(SimulatedTactile, DeactivateLowersEveryPin) {
  SimulatedTactileDevice d = started();
  d.write(kT, 0xFFFFu);
  for (int i = 0; i < 16; ++i) EXPECT_FLOAT_EQ(shown(d, kT + 24 * kMs)[i], 1.0f) << i;
  d.deactivate();  // from the latest time seen: kT + 24 ms
  EXPECT_EQ(d.targets(), 0u);
  for (int i = 0; i < 16; ++i) EXPECT_FLOAT_EQ(shown(d, kT + 36 * kMs)[i], 0.5f) << i;
  for (int i = 0; i < 16; ++i) EXPECT_FLOAT_EQ(shown(d, kT + 48 * kMs)[i], 0.0f) << i;
  // writes are ignored until activated again
  d.write(kT + 50 * kMs, 0xFFFFu);
  EXPECT_FLOAT_EQ(shown(d, kT + 74 * kMs)[0], 0.0f);
  d.activate();
  d.write(kT + 80 * kMs, 1u);
  EXPECT_FLOAT_EQ(shown(d, kT + 92 * kMs)[0], 0.5f);
}

TEST(SimulatedTactile, ShownWritesOnlyTheExistingPinsUpToCount) {
  SimulatedTactileDevice d = started({.rows = 2, .cols = 3});
  EXPECT_EQ(d.rows(), 2);
  EXPECT_EQ(d.cols(), 3);
  d.write(kT, ~0u);  // bits beyond 6 pins are ignored
  EXPECT_EQ(d.targets(), 0x3Fu);
  std::array<float, 8> levels;
  levels.fill(-1.0f);
  d.shown(kT + 24 * kMs, levels.data(), 4);
  for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(levels[i], 1.0f) << i;
  for (int i = 4; i < 8; ++i) EXPECT_FLOAT_EQ(levels[i], -1.0f) << i;
  levels.fill(-1.0f);
  d.shown(kT + 24 * kMs, levels.data(), 8);
  for (int i = 0; i < 6; ++i) EXPECT_FLOAT_EQ(levels[i], 1.0f) << i;
  for (int i = 6; i < 8; ++i) EXPECT_FLOAT_EQ(levels[i], -1.0f) << i;
}

TEST(SimulatedTactile, ThirtyTwoPinsFitMoreAreRefused) {
  SimulatedTactileDevice d = started({.rows = 4, .cols = 8});
  d.write(kT, 1u << 31);
  EXPECT_FLOAT_EQ(shown(d, kT + 24 * kMs)[31], 1.0f);
  const SimulatedTactileParams bad[] = {{.rows = 8, .cols = 5}, {.rows = 0, .cols = 4}, {.rows = 4, .cols = -1},
                                        {.rows = 1 << 16, .cols = 1 << 16}, {.rows = 4, .cols = 4, .rise_time_s = 0.0}};
  for (const auto& p : bad) {
    SimulatedTactileDevice refused(p);
    try {
      refused.configure();
      ADD_FAILURE() << p.rows << " x " << p.cols << " accepted";
    } catch (const config::Error& e) {
      EXPECT_NE(std::string(e.what()).find("fix:"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace enact::devices
