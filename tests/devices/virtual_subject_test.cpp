// The virtual subject on its own: its file (refused with file:line and the fix), its
// reaction delay, its pins (read against what they showed in the air, ignored when told),
// determinism, and the simulated device driven by it and by a scripted hand through one
// mechanism.
#include "core/devices/virtual_subject.h"

#include <gtest/gtest.h>

#include <string>

#include "core/config/yaml.h"
#include "core/devices/simulated_force.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/refusal.h"
#include "tests/support/test_util.h"

namespace enact::devices {
namespace {

using math::Vec3;

using test::kMs;
const Vec3 kStart{0.0, 0.0, 0.013};

// a subject that reacts in 100 ms, with no noise (it settles 150 ms: the delay and 50 ms)
SubjectParams quiet() {
  SubjectParams p;
  p.settle_s = 0.01;
  p.reaction_delay_s = 0.1;
  p.motor_noise = 0.0;
  p.motor_noise_floor_m_per_s = 0.0;
  p.between_subjects = 0.0;
  return p;
}

// what the hand feels: the handle at `handle`, pushed with `force`
HandFeel felt(const Vec3& handle, const Vec3& force = {}) { return {handle, {}, force}; }

std::string error_of(const std::string& yaml) {
  return test::error_of_file("subject.yaml", yaml, [](const std::string& path) { load_subject(path); });
}

TEST(VirtualSubject, FileValuesAreRead) {
  test::TempDir dir;
  const std::string path = dir.file("s.yaml");
  test::write_file(path, "name: careful\nspeed_m_per_s: 0.005\ntactile_use: 0.25\nroute: {headings_deg: [0, 90], lengths_m: [0.01, 0.02]}\n");
  const SubjectParams p = load_subject(path);
  EXPECT_EQ(p.name, "careful");
  EXPECT_EQ(p.speed_m_per_s, 0.005);
  EXPECT_EQ(p.tactile_use, 0.25);
  ASSERT_EQ(p.route_headings_deg.size(), 2u);
  EXPECT_EQ(p.route_headings_deg[1], 90.0);
  EXPECT_EQ(p.route_lengths_m[1], 0.02);
  EXPECT_EQ(p.press_n, SubjectParams{}.press_n) << "keys left out keep their defaults";
}

TEST(VirtualSubject, ShippedSubjectLoads) {
  const SubjectParams p = load_subject(test::source_path("launch/experiments/subjects/baseline.yaml"));
  EXPECT_EQ(p.name, "baseline");
  EXPECT_EQ(p.route_headings_deg.size(), 3u);
}

TEST(VirtualSubject, BadFilesNameTheLineAndTheFix) {
  const std::string unknown = error_of("name: x\nspeeed_m_per_s: 0.01\n");
  EXPECT_NE(unknown.find("subject.yaml:2:"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("speeed_m_per_s"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("fix:"), std::string::npos) << unknown;

  const std::string range = error_of("name: x\n\ntactile_use: 1.5\n");
  EXPECT_NE(range.find("subject.yaml:3:"), std::string::npos) << range;
  EXPECT_NE(range.find("tactile_use is 1.5"), std::string::npos) << range;

  const std::string route = error_of("route:\n  headings_deg: [45, -45]\n  lengths_m: [0.02]\n");
  EXPECT_NE(route.find("subject.yaml:3:"), std::string::npos) << route;
  EXPECT_NE(route.find("differ in length"), std::string::npos) << route;

  const std::string text = error_of("press_n: hard\n");
  EXPECT_NE(text.find("subject.yaml:1:"), std::string::npos) << text;
}

TEST(VirtualSubject, ParamsBuiltInCodeAreChecked) {
  SubjectParams p;
  p.reaction_delay_s = -0.1;
  try {
    VirtualSubject s(p, 1, 1);
    ADD_FAILURE() << "a negative delay was accepted";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("reaction_delay_s"), std::string::npos) << e.what();
  }
}

TEST(VirtualSubject, ReactsOneDelayAfterTouching) {
  VirtualSubject s(quiet(), 1, 1);
  s.reset({kStart, 300.0});
  // settle, then descend in the air; contact felt from 200 ms on
  const std::int64_t touch_ns = 200 * kMs;
  double z_at_touch = 0.0;
  double previous = kStart.z;
  for (std::int64_t t = 0; t <= 400 * kMs; t += kMs) {
    const bool touching = t >= touch_ns;
    const Vec3 target = s.target(t, felt(kStart, {0.0, 0.0, touching ? 1.0 : 0.0}));
    if (t == touch_ns) z_at_touch = target.z;
    // still lowering until the touch is felt a reaction delay later, never before
    if (t > 160 * kMs && t <= touch_ns + 100 * kMs) {
      EXPECT_LT(target.z, previous) << "t " << t / kMs << " ms";
    }
    previous = target.z;
  }
  EXPECT_LT(z_at_touch, kStart.z);
  EXPECT_EQ(s.phase(), VirtualSubject::Phase::follow) << "once the touch is felt it follows the top";
}

TEST(VirtualSubject, PinsDifferentFromTheAirMeanContact) {
  // pins all up in the air (inverted pins): the subject reads lowered pins as contact
  VirtualSubject s(quiet(), 1, 1);
  s.reset({kStart, 300.0});
  float up[16], down[16];
  for (int i = 0; i < 16; ++i) up[i] = 1.0f, down[i] = 0.0f;
  s.feel_pins(up, 4, 4);
  std::int64_t t = 0;
  for (; t <= 160 * kMs; t += kMs) s.target(t, felt(kStart));
  ASSERT_EQ(s.phase(), VirtualSubject::Phase::descend);
  s.feel_pins(down, 4, 4);
  for (; t <= 400 * kMs; t += kMs) s.target(t, felt(kStart));
  EXPECT_EQ(s.phase(), VirtualSubject::Phase::follow) << "no force, but the pins changed: contact";
}

TEST(VirtualSubject, IgnoresPinsWhenTactileUseIsZero) {
  SubjectParams p = quiet();
  p.tactile_use = 0.0;
  VirtualSubject s(p, 1, 1);
  s.reset({kStart, 300.0});
  float down[16] = {}, up[16];
  for (float& l : up) l = 1.0f;
  s.feel_pins(down, 4, 4);
  std::int64_t t = 0;
  for (; t <= 160 * kMs; t += kMs) s.target(t, felt(kStart));
  s.feel_pins(up, 4, 4);
  for (; t <= 400 * kMs; t += kMs) s.target(t, felt(kStart));
  EXPECT_EQ(s.phase(), VirtualSubject::Phase::descend) << "pins alone are not contact for a subject that ignores them";
}

TEST(VirtualSubject, SameSeedsSameTargetsAfterReset) {
  SubjectParams p;  // with noise
  VirtualSubject a(p, 3, 7), b(p, 3, 7), c(p, 3, 8);
  a.reset({kStart, 300.0});
  b.reset({kStart, 300.0});
  c.reset({kStart, 300.0});
  bool differs = false;
  for (std::int64_t t = 0; t <= 2000 * kMs; t += kMs / 10) {
    const Vec3 ta = a.target(t, felt(kStart));
    EXPECT_EQ(ta, b.target(t, felt(kStart)));
    differs = differs || !(ta == c.target(t, felt(kStart)));
  }
  EXPECT_TRUE(differs) << "another noise seed gives other motor noise";
  // reset restarts the trial: the same targets again
  a.reset({kStart, 300.0});
  b.reset({kStart, 300.0});
  for (std::int64_t t = 0; t <= 500 * kMs; t += kMs) EXPECT_EQ(a.target(t, felt(kStart)), b.target(t, felt(kStart)));
}

TEST(VirtualSubject, SubjectSeedDrawsTraits) {
  SubjectParams p;
  p.between_subjects = 0.2;
  VirtualSubject a(p, 1, 1), b(p, 2, 1);
  EXPECT_NE(a.speed_m_per_s(), b.speed_m_per_s());
  EXPECT_NE(a.reaction_delay_s(), b.reaction_delay_s());
  p.between_subjects = 0.0;
  VirtualSubject c(p, 1, 1);
  EXPECT_EQ(c.speed_m_per_s(), p.speed_m_per_s);
}

TEST(VirtualSubject, TargetAllocatesNothing) {
  VirtualSubject s(SubjectParams{}, 1, 1);
  s.reset({kStart, 300.0});
  float levels[16] = {};
  std::size_t allocations = 0;
  {
    test::AllocGuard guard;
    for (std::int64_t t = 0; t <= 3000 * kMs; t += kMs / 10) {
      s.feel_pins(levels, 4, 4);
      s.target(t, felt(kStart, {0.0, 0.0, t > 500 * kMs ? 1.0 : 0.0}));
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
}

TEST(VirtualSubject, DriveTheSimulatedDeviceThroughItsHandImpedance) {
  SimulatedForceParams f;
  f.subject = test::source_path("launch/experiments/subjects/baseline.yaml");
  f.start_m = kStart;
  SimulatedForceDevice device(f);
  device.configure();
  device.activate();
  ASSERT_NE(dynamic_cast<VirtualSubject*>(device.simulated_hand()), nullptr);
  ForceSample sample;
  // nothing under the hand: it settles, then lowers the handle
  for (std::int64_t t = 0; t <= 1000 * kMs; t += kMs / 5) device.read(t, sample);
  EXPECT_LT(sample.position_m.z, kStart.z - 0.005);
}

TEST(VirtualSubject, HandPathAndSubjectTogetherAreRefused) {
  SimulatedForceParams f;
  f.subject = test::source_path("launch/experiments/subjects/baseline.yaml");
  f.hand_path = test::source_path("launch/paths/bridge_walk.csv");
  SimulatedForceDevice device(f);
  try {
    device.configure();
    ADD_FAILURE() << "both accepted";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("not both"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace enact::devices
