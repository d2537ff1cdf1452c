// Parameter changes of a running simulator: checked by the planner (stiffness and damping
// against the passivity bound of the stability analysis), applied between steps by
// Simulator::apply without allocating.
#include "core/sim/params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "core/sim/simulator.h"
#include "tests/support/alloc_guard.h"
#include "tests/sim/sim_test_util.h"
#include "tests/support/test_util.h"

namespace enact::sim {
namespace {

// the middle of the first segment's top, 1 mm deep: 14 grid masses touch
using test_util::kPressed;
const math::Vec3 kAbove{0.0, -0.0148492, 0.020};
constexpr std::int64_t kPeriod_ns = 200'000;

// the parameters of a scene file (a path under the source tree, or absolute)
SimParams on_scene(const std::string& scene = "launch/scenes/bridge.yaml") {
  SimParams p;
  p.scene = scene.starts_with("/") ? scene : test::source_path(scene);
  return p;
}

ParamValue number(double v) { return {v, std::nullopt, std::nullopt}; }
ParamValue text(const std::string& v) { return {std::nullopt, v, std::nullopt}; }
ParamValue flag(bool v) { return {std::nullopt, std::nullopt, v}; }

// the bridge scene with another contact stiffness, in `dir`
std::string bridge_with_stiffness(const test::TempDir& dir, const std::string& stiffness) {
  std::string scene = test::read_file(test::source_path("launch/scenes/bridge.yaml"));
  scene = std::regex_replace(scene, std::regex("stiffness_n_per_m: 6000"), "stiffness_n_per_m: " + stiffness);
  const std::string path = dir.file("bridge.yaml");
  test::write_file(path, scene);
  return path;
}

struct Rig {
  Simulator sim;
  std::int64_t n = 0;
  explicit Rig(SimParams p = on_scene()) {
    sim.configure(p);
    sim.activate(0);
  }
  const StepOutput& step(const math::Vec3& at) { return sim.step(n++ * kPeriod_ns, at); }
  ParamApplied apply(ParamPlanner& planner, const std::string& name, const ParamValue& v) {
    const ParamPlan plan = planner.plan(name, v, 7);
    EXPECT_TRUE(plan.accepted) << name << ": " << plan.reason;
    return sim.apply(plan.change, 123);
  }
};

// the two-boxes scene with friction on the body's contacts (static 0.6, dynamic 0.4), in `dir`
std::string boxes_with_friction(const test::TempDir& dir) {
  std::string scene = test::read_file(test::source_path("launch/scenes/two_boxes.yaml"));
  scene = std::regex_replace(scene, std::regex("damping_n_s_per_m: 0\\.01\\}"),
                             "damping_n_s_per_m: 0.01, friction: {static: 0.6, dynamic: 0.4, stiffness_n_per_m: 2000}}");
  const std::string path = dir.file("boxes.yaml");
  test::write_file(path, scene);
  return path;
}

// the body pressed 0.5 mm into the left box's top and dragged along x at 10 mm/s, at step n
math::Vec3 dragged(std::int64_t n) { return {-0.012 + 0.010 * static_cast<double>(n) * kPeriod_ns * 1e-9, 0.003, 0.0095}; }

TEST(ParamPlanner, BridgeStiffnessCanGoDownButNotPastTheSceneAsLoaded) {
  // the bridge as shipped is past the ERGOS passivity bound (`enact check` warns): with all
  // 17 body points in contact (bridge and floor are disjoint: one contact each),
  // K T/2 + B = 17 x 6000 x 1e-4 + 17 x 0.02 = 10.54 > b = 6 N s/m. Live changes may not go
  // further than it.
  Rig rig;
  ParamPlanner planner(rig.sim);
  EXPECT_NEAR(planner.passivity_envelope_n_s_per_m(), 10.54, 1e-9);
  EXPECT_TRUE(planner.plan("stiffness_n_per_m", number(3000.0), 1).accepted);
  EXPECT_TRUE(planner.plan("stiffness_n_per_m", number(6000.0), 2).accepted);
  const ParamPlan refused = planner.plan("stiffness_n_per_m", number(6001.0), 3);
  EXPECT_FALSE(refused.accepted);
  const ParamPlan wild = planner.plan("stiffness_n_per_m", number(1e6), 4);
  ASSERT_FALSE(wild.accepted);
  EXPECT_NE(wild.reason.find("Colgate & Schenkel"), std::string::npos) << wild.reason;
  EXPECT_NE(wild.reason.find("fix: at most 6000 N/m"), std::string::npos) << wild.reason;
  EXPECT_EQ(planner.stiffness_n_per_m(), 6000.0);  // the refused values left the mirror alone
}

// the planner's envelope is the one function enact check prints, and its refusal says it
TEST(ParamPlanner, EnvelopeIsTheSceneFunctionsAndTheRefusalSaysIt) {
  Simulator sim;
  SimParams p;
  p.scene = test::source_path("launch/scenes/bridge.yaml");
  sim.configure(p);
  ParamPlanner planner(sim);
  EXPECT_EQ(planner.passivity_envelope_n_s_per_m(), passivity_envelope(sim.model()));
  EXPECT_NEAR(passivity_envelope(sim.model()), 10.54, 0.005);
  const ParamPlan refused = planner.plan("stiffness_n_per_m", {9000.0, {}, {}}, 1);
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(refused.reason.find("past 10.54 N s/m"), std::string::npos) << refused.reason;
}

TEST(ParamPlanner, AThresholdIsFromZeroToFiftyMillimetres) {
  Rig rig;
  ParamPlanner planner(rig.sim);
  EXPECT_TRUE(planner.plan("threshold_m", number(0.05), 1).accepted);
  for (double wild : {1e12, 0.0501, -0.001}) {
    const ParamPlan refused = planner.plan("threshold_m", number(wild), 2);
    EXPECT_FALSE(refused.accepted) << wild;
    EXPECT_NE(refused.reason.find("from 0 to 0.05 m"), std::string::npos) << refused.reason;
  }
}

TEST(ParamPlanner, PassiveSceneMayRiseUpToTheDeviceDamping) {
  // 1000 N/m per pair: K T/2 + B = 17 x 1000 x 1e-4 + 0.34 = 2.04 N s/m, passive on the ERGOS
  // (b = 6): the envelope is b, reached at (6 - 0.34) / (17 x 1e-4) = 3329.41 N/m
  const test::TempDir dir;
  Rig rig(on_scene(bridge_with_stiffness(dir, "1000")));
  ParamPlanner planner(rig.sim);
  EXPECT_DOUBLE_EQ(planner.passivity_envelope_n_s_per_m(), 6.0);
  EXPECT_TRUE(planner.plan("stiffness_n_per_m", number(3300.0), 1).accepted);
  const ParamPlan p = planner.plan("stiffness_n_per_m", number(3400.0), 2);
  ASSERT_FALSE(p.accepted);
  EXPECT_NE(p.reason.find("at most 3329.41 N/m"), std::string::npos) << p.reason;
}

TEST(ParamPlanner, DampingIsCheckedAgainstTheSameBound) {
  Rig rig;
  ParamPlanner planner(rig.sim);
  EXPECT_TRUE(planner.plan("damping_n_s_per_m", number(0.01), 1).accepted);
  EXPECT_TRUE(planner.plan("damping_n_s_per_m", text("0.02"), 2).accepted);
  const ParamPlan p = planner.plan("damping_n_s_per_m", number(1.0), 3);
  ASSERT_FALSE(p.accepted);
  EXPECT_NE(p.reason.find("fix: at most 0.02 N s/m"), std::string::npos) << p.reason;
  EXPECT_FALSE(planner.plan("damping_n_s_per_m", number(-1.0), 4).accepted);
  EXPECT_FALSE(planner.plan("damping_n_s_per_m", number(NAN), 5).accepted);
  EXPECT_FALSE(planner.plan("damping_n_s_per_m", text("soft"), 6).accepted);
}

TEST(ParamPlanner, ModelThresholdTrialAndUnknownNames) {
  Rig rig;
  ParamPlanner planner(rig.sim);
  const ParamPlan cm3 = planner.plan("model", text("CM3"), 11);
  ASSERT_TRUE(cm3.accepted) << cm3.reason;
  EXPECT_EQ(cm3.change.request_id, 11u);
  EXPECT_STREQ(cm3.change.model.name, "CM3");
  EXPECT_EQ(cm3.change.model.pins, haptics::PinDrive::inverted);
  EXPECT_EQ(planner.computer_model().name, "CM3");
  const ParamPlan bad = planner.plan("model", text("CM9"), 12);
  ASSERT_FALSE(bad.accepted);
  EXPECT_NE(bad.reason.find("CM0, CM1, CM2, CM3, P, T, PT"), std::string::npos) << bad.reason;
  EXPECT_FALSE(planner.plan("model", number(1.0), 13).accepted);
  const ParamPlan missing = planner.plan("model", text("no/such/model.yaml"), 14);
  ASSERT_FALSE(missing.accepted);
  EXPECT_NE(missing.reason.find("no/such/model.yaml"), std::string::npos) << missing.reason;

  EXPECT_FALSE(planner.plan("threshold_m", number(-0.001), 15).accepted);
  const ParamPlan t = planner.plan("threshold_m", text("0.002"), 16);
  ASSERT_TRUE(t.accepted) << t.reason;
  EXPECT_EQ(t.change.value, 0.002);

  EXPECT_EQ(planner.plan("trial", text("start"), 17).change.kind, ParamKind::trial_start);
  EXPECT_EQ(planner.plan("trial", flag(false), 18).change.kind, ParamKind::trial_stop);
  EXPECT_FALSE(planner.plan("trial", text("maybe"), 19).accepted);

  const ParamPlan unknown = planner.plan("stifness_n_per_m", number(1.0), 20);
  ASSERT_FALSE(unknown.accepted);
  EXPECT_NE(unknown.reason.find("stiffness_n_per_m"), std::string::npos) << unknown.reason;
}

TEST(ParamPlanner, ModelFromAFileAndOneWithATooLongName) {
  const test::TempDir dir;
  test::write_file(dir.file("edges.yaml"), "name: edges\nforce: [0, 3, 12, 15]\npins: contact\n");
  test::write_file(dir.file("long.yaml"), "name: " + std::string(kMaxModelName + 1, 'x') + "\nforce: grid\n");
  Rig rig;
  ParamPlanner planner(rig.sim);
  const ParamPlan edges = planner.plan("model", text(dir.file("edges.yaml")), 1);
  ASSERT_TRUE(edges.accepted) << edges.reason;
  EXPECT_EQ(edges.change.model.force_grid_mask, (1u << 0) | (1u << 3) | (1u << 12) | (1u << 15));
  EXPECT_FALSE(planner.plan("model", text(dir.file("long.yaml")), 2).accepted);
}

TEST(SimulatorApply, StiffnessDownBlendsOverTheRampWithoutAJolt) {
  Rig rig;
  ParamPlanner planner(rig.sim);
  for (int i = 0; i < 3; ++i) rig.step(kPressed);  // at rest: the force is k x depth
  const double before = rig.step(kPressed).force_n.z;
  ASSERT_GT(before, 0.0);
  rig.apply(planner, "stiffness_n_per_m", number(3000.0));
  // the body held still: the old force, then to half of it in even steps over 50 ms (250 steps)
  double last = rig.step(kPressed).force_n.z;
  EXPECT_EQ(last, before);
  for (int i = 0; i < 250; ++i) {
    const double f = rig.step(kPressed).force_n.z;
    EXPECT_NEAR(last - f, before / 2.0 / 250.0, 1e-9 * before) << "step " << i;
    last = f;
  }
  EXPECT_NEAR(last, before / 2.0, 1e-9 * before);
  EXPECT_EQ(rig.step(kPressed).force_n.z, last);
}

TEST(SimulatorApply, StiffnessUpNeverReleasesThePenetrationAtOnce) {
  const test::TempDir dir;
  Rig rig(on_scene(bridge_with_stiffness(dir, "1000")));
  ParamPlanner planner(rig.sim);
  for (int i = 0; i < 3; ++i) rig.step(kPressed);
  const double before = rig.step(kPressed).force_n.z;
  ASSERT_GT(before, 0.0);
  rig.apply(planner, "stiffness_n_per_m", number(3000.0));
  // the body held still 1 mm deep: the force it had, then the surface rises back gently (at
  // most the ERGOS's 5 N/ms, i.e. 1 N a step) to the new law's 3 x
  double last = before;
  for (int i = 0; i < 2000; ++i) {
    const double f = rig.step(kPressed).force_n.z;
    EXPECT_LE(std::abs(f - last), 1.0 + 1e-9) << "step " << i;
    last = f;
  }
  EXPECT_NEAR(last, 3.0 * before, 1e-9 * before);
}

// reentry_speed_m_per_s (a parameter of enact-sim and enact-rt's sim): a tenth of the speed
// brings the surface back about ten times more slowly, each step within its bound
TEST(SimulatorApply, TheReentrySpeedBoundsHowFastTheSurfaceRisesBack) {
  const test::TempDir dir;
  const std::string scene = bridge_with_stiffness(dir, "1000");
  // steps from the change until the new law's force, and the largest rise of one step
  auto rise = [&](double speed_m_per_s, double& largest_n) {
    SimParams p = on_scene(scene);
    p.reentry_speed_m_per_s = speed_m_per_s;
    Rig rig(p);
    ParamPlanner planner(rig.sim);
    for (int i = 0; i < 3; ++i) rig.step(kPressed);
    const double before = rig.step(kPressed).force_n.z;
    rig.apply(planner, "stiffness_n_per_m", number(3000.0));
    double last = before;
    largest_n = 0.0;
    for (int i = 1; i <= 100000; ++i) {
      const double f = rig.step(kPressed).force_n.z;
      largest_n = std::max(largest_n, std::abs(f - last));
      last = f;
      if (std::abs(f - 3.0 * before) < 1e-9 * before) return i;
    }
    return -1;
  };
  double fast_n = 0.0, slow_n = 0.0;
  const int fast = rise(0.01, fast_n), slow = rise(0.001, slow_n);
  ASSERT_GT(fast, 0);
  ASSERT_GT(slow, 0);
  std::printf("the surface back in %d steps at 10 mm/s (largest step %.4f N), %d at 1 mm/s (%.4f N)\n", fast, fast_n, slow, slow_n);
  // the rise is the speed's: a tenth of it, a tenth of the largest step, ten times the steps
  // (give or take the last partial step)
  EXPECT_NEAR(slow_n, fast_n / 10.0, 0.01 * fast_n / 10.0);
  EXPECT_NEAR(static_cast<double>(slow) / fast, 10.0, 0.1);
}

TEST(SimulatorApply, ModelAndThresholdChangeForceAndPins) {
  Rig rig;
  ParamPlanner planner(rig.sim);
  const StepOutput& out = rig.step(kPressed);
  const std::uint32_t pins_cm1 = out.pins;
  ASSERT_NE(pins_cm1, 0u);
  rig.apply(planner, "model", text("CM3"));
  EXPECT_EQ(rig.step(kPressed).pins, 0xffffu & ~pins_cm1);
  EXPECT_EQ(rig.sim.computer_model().name, "CM3");
  // 2 mm threshold, 1 mm deep: the force fades out over the ramp (50 ms, 250 steps), the
  // pins still follow contact (CM3: inverted)
  rig.apply(planner, "threshold_m", number(0.002));
  const double before = rig.step(kPressed).force_n.z;
  EXPECT_GT(before, 0.0);
  for (int i = 0; i < 250; ++i) rig.step(kPressed);
  const StepOutput& deep = rig.step(kPressed);
  EXPECT_EQ(deep.force_n.z, 0.0);
  EXPECT_EQ(deep.pins, 0xffffu & ~pins_cm1);
  EXPECT_EQ(rig.sim.computer_model().threshold_m, 0.002);
}

TEST(SimulatorApply, TrialStopFreezesTheTaskAndStartBeginsANewOne) {
  SimParams p = on_scene();
  p.task.min_fall_s = 0.01;  // a fall after 50 steps off the top
  Rig rig(p);
  ParamPlanner planner(rig.sim);
  for (int i = 0; i < 10; ++i) rig.step(kPressed);
  // the trial ends with the next step
  rig.apply(planner, "trial", text("stop"));
  rig.step(kPressed);
  EXPECT_FALSE(rig.sim.trial_running());
  for (int i = 0; i < 200; ++i) EXPECT_EQ(rig.step(kAbove).event.kind, task::TaskEventKind::none);
  EXPECT_EQ(rig.sim.metrics().falls, 0);
  // a new trial from the next step on
  rig.apply(planner, "trial", text("start"));
  int falls = 0;
  for (int i = 0; i < 200; ++i) falls += rig.step(kAbove).event.kind == task::TaskEventKind::fall_start;
  EXPECT_TRUE(rig.sim.trial_running());
  EXPECT_EQ(falls, 1);
  // the new trial began at the start command, 211 steps in: it lasted 200 steps
  EXPECT_NEAR(rig.sim.metrics().time_total_s, 199 * 2e-4, 1e-9);
}

TEST(SimulatorApply, ResetRestartsTheModelAndTheTrial) {
  Rig rig;
  ParamPlanner planner(rig.sim);
  for (int i = 0; i < 50; ++i) rig.step(kPressed);
  ASSERT_EQ(rig.sim.state().steps, 50);
  const ParamApplied a = rig.apply(planner, "reset", flag(true));
  EXPECT_EQ(a.kind, ParamKind::reset);
  EXPECT_EQ(a.request_id, 7u);
  EXPECT_EQ(a.time_ns, 123);
  EXPECT_EQ(rig.sim.state().steps, 0);
  rig.step(kPressed);
  EXPECT_NEAR(rig.sim.metrics().time_total_s, 0.0, 1e-12);
}

TEST(SimulatorApply, AppliesEveryKindOfChangeWithoutAllocating) {
  const test::TempDir dir;
  const std::string long_name(kMaxModelName, 'm');
  test::write_file(dir.file("long.yaml"), "name: " + long_name + "\nforce: grid\npins: contact\n");
  Rig rig;
  ParamPlanner planner(rig.sim);
  // planned off the loop (this allocates), applied on it
  std::vector<ParamChange> changes;
  for (const auto& [name, value] : std::vector<std::pair<std::string, ParamValue>>{
           {"model", text(dir.file("long.yaml"))}, {"model", text("CM2")}, {"threshold_m", number(0.001)},
           {"stiffness_n_per_m", number(5000.0)}, {"damping_n_s_per_m", number(0.01)}, {"reset", flag(true)},
           {"reposition", flag(true)}, {"trial", text("stop")}, {"trial", text("start")}}) {
    const ParamPlan p = planner.plan(name, value, changes.size() + 1);
    ASSERT_TRUE(p.accepted) << name << ": " << p.reason;
    changes.push_back(p.change);
  }
  rig.step(kPressed);
  std::size_t allocations = 0;
  {
    const test::AllocGuard guard;
    for (const ParamChange& c : changes) {
      rig.sim.apply(c, 0);
      rig.step(kPressed);
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(rig.sim.computer_model().name, "CM2");
  EXPECT_EQ(rig.sim.computer_model().threshold_m, 0.001);
}

}  // namespace
}  // namespace enact::sim

namespace enact::sim {
namespace {

TEST(LiveNumbers, SlidingFrictionIsRefusedWithoutFrictionAndAboveTheStaticCoefficient) {
  const LiveNumber* friction = find_live_number("friction_dynamic");
  ASSERT_NE(friction, nullptr);
  Rig bridge;
  ParamPlanner on_bridge(bridge.sim);
  const ParamPlan none = on_bridge.plan("friction_dynamic", number(0.3), 1);
  EXPECT_FALSE(none.accepted);
  EXPECT_NE(none.reason.find("no contact of the scene's body has friction"), std::string::npos) << none.reason;
  EXPECT_NE(none.reason.find("fix: give its contacts friction:"), std::string::npos) << none.reason;
  test::TempDir dir;
  Rig boxes(on_scene(boxes_with_friction(dir)));
  ParamPlanner planner(boxes.sim);
  EXPECT_EQ(planner.value(*friction), 0.4);
  const ParamPlan above = planner.plan("friction_dynamic", number(0.7), 2);
  EXPECT_FALSE(above.accepted);
  EXPECT_NE(above.reason.find("above friction.static 0.6"), std::string::npos) << above.reason;
  const ParamPlan negative = planner.plan("friction_dynamic", number(-0.1), 3);
  EXPECT_FALSE(negative.accepted);
  EXPECT_NE(negative.reason.find("friction_dynamic must be a number >= 0"), std::string::npos) << negative.reason;
  EXPECT_EQ(planner.value(*friction), 0.4) << "a refusal leaves the mirror";
  EXPECT_TRUE(planner.plan("friction_dynamic", number(0.1), 4).accepted);
  EXPECT_EQ(planner.value(*friction), 0.1);
}

// a body dragged along a box's top slides, held back by the sliding friction: a live change
// to a quarter of it holds the body back less once the change has blended in, and a keyframe
// saved after the change restores it (a simulator restored without it would slide at 0.4)
TEST(LiveNumbers, ALowerSlidingFrictionHoldsTheDraggedBodyBackLessAndAKeyframeKeepsIt) {
  test::TempDir dir;
  const SimParams scene = on_scene(boxes_with_friction(dir));
  Rig changed(scene), kept(scene);
  ParamPlanner planner(changed.sim);
  double held_before = 0.0, held_changed = 0.0, held_kept = 0.0;
  for (std::int64_t n = 0; n < 1500; ++n) {
    if (n == 500) changed.apply(planner, "friction_dynamic", number(0.1));
    const double a = changed.sim.step(n * kPeriod_ns, dragged(n)).force_n.x, b = kept.sim.step(n * kPeriod_ns, dragged(n)).force_n.x;
    if (n >= 300 && n < 500) held_before += a;
    if (n >= 1000) {
      held_changed += a;
      held_kept += b;
    }
  }
  ASSERT_LT(held_kept, 0.0) << "the dragged body should be held back (force against +x)";
  EXPECT_NEAR(held_before / 200.0, held_kept / 500.0, 0.2 * std::abs(held_kept / 500.0)) << "sliding at 0.4 before the change";
  EXPECT_LT(std::abs(held_changed), 0.5 * std::abs(held_kept)) << held_changed / 500.0 << " N against " << held_kept / 500.0 << " N";

  Keyframe saved;
  changed.sim.save(saved);
  std::string bytes;
  pack(saved, bytes);
  Simulator restored;
  restored.configure(scene);
  Keyframe k;
  restored.save(k);
  ASSERT_TRUE(unpack(bytes, k));
  restored.restore(k);
  for (std::int64_t n = 1500; n < 1700; ++n) {
    const double a = changed.sim.step(n * kPeriod_ns, dragged(n)).force_n.x, b = restored.step(n * kPeriod_ns, dragged(n)).force_n.x;
    ASSERT_EQ(a, b) << "step " << n;
  }
}

}  // namespace
}  // namespace enact::sim
