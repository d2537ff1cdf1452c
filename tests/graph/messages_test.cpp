// The bus messages filled from the components' state (core/graph/messages.h): the pins'
// motion a TactileShown carries gives, at any later time, what the device itself shows.
#include "core/graph/messages.h"

#include <gtest/gtest.h>

#include "core/devices/simulated_tactile.h"
#include "tests/support/test_util.h"

namespace enact::graph {
namespace {

constexpr std::int64_t kShownFrom_ns = 5'000 * test::kMs;  // an arbitrary start time

TEST(TactileShownMotion, TheMotionSentIsWhatTheDeviceShowsAtEveryLaterTime) {
  devices::SimulatedTactileDevice d({.rows = 4, .cols = 4, .rise_time_s = 0.024});
  d.configure();
  d.activate();
  d.write(kShownFrom_ns, 0b1010'0101u);
  d.write(kShownFrom_ns + 7 * test::kMs, 0b0110'0110u);  // some pins reverse mid-stroke, some start
  float levels[16] = {};
  d.shown(kShownFrom_ns + 7 * test::kMs, levels, 16);
  devices::PinMotion motion;
  ASSERT_TRUE(d.motion(motion));
  msgs::TactileShown m;
  fill(m, 4, 4, levels, 2, &motion);
  msgs::TactileShown received;
  ASSERT_TRUE(received.ParseFromString(m.SerializeAsString()));
  devices::PinMotion got;
  ASSERT_TRUE(get(received, got));
  // every pin, every 0.2 ms tick until the strokes end: bit for bit the device's own level
  int moving = 0;
  for (std::int64_t t = kShownFrom_ns + 7 * test::kMs; t <= kShownFrom_ns + 40 * test::kMs; t += 200'000) {
    d.shown(t, levels, 16);
    for (int i = 0; i < 16; ++i) {
      ASSERT_EQ(static_cast<float>(got.level(i, t)), levels[i]) << "pin " << i << " at " << static_cast<double>(t - kShownFrom_ns) / 1e6 << " ms";
      moving += levels[i] > 0.0f && levels[i] < 1.0f;
    }
  }
  EXPECT_GT(moving, 100) << "the pins were mid-stroke over many ticks";
}

TEST(TactileShownMotion, NoMotionOrABadOneIsNotTaken) {
  float levels[16] = {};
  msgs::TactileShown m;
  fill(m, 4, 4, levels, 1, nullptr);
  devices::PinMotion got;
  EXPECT_FALSE(get(m, got)) << "a device that does not know the motion sends none";
  devices::PinMotion motion;
  fill(m, 4, 4, levels, 1, &motion);
  EXPECT_TRUE(get(m, got));
  m.mutable_motion()->set_stroke_ns(0.0);
  EXPECT_FALSE(get(m, got)) << "a stroke that takes no time";
  m.mutable_motion()->set_stroke_ns(24e6);
  for (int i = 0; i < 17; ++i) {
    m.mutable_motion()->add_from_level(0.0);
    m.mutable_motion()->add_from_ns(0);
  }
  EXPECT_FALSE(get(m, got)) << "more than 32 pins";
  fill(m, 4, 4, levels, 1, nullptr);
  EXPECT_FALSE(m.has_motion()) << "a message reused without motion carries none";
}

}  // namespace
}  // namespace enact::graph
