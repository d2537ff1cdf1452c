// Virtual subjects on the bridge, in simulated time through the co-located tick: runs are
// reproducible, the subject feels the pins only through the tactile device, tactile cues
// help it, and the tick with a subject holding the device allocates nothing.
#include "core/experiment/virtual_trial.h"

#include <gtest/gtest.h>

#include <string>

#include "core/devices/safety.h"
#include "core/node/colocated.h"
#include "core/node/components.h"
#include "core/params/node_params.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/test_util.h"

namespace enact::experiment {
namespace {

const std::string kStart = "-0.0074246,-0.0222739,0.013";

std::string baseline() { return test::source_path("launch/experiments/subjects/baseline.yaml"); }

VirtualTrialParams trial(const std::string& model, int subject, const std::string& subject_file = baseline(), double limit_s = 60.0) {
  VirtualTrialParams p;
  p.sim.set("scene", test::source_path("launch/scenes/bridge.yaml"));
  p.sim.set("model", model);
  p.ffd.set("subject", subject_file);
  p.ffd.set("subject_seed", std::to_string(subject));
  p.ffd.set("noise_seed", std::to_string(1000 + subject));
  p.ffd.set("start_m", kStart);
  p.limit_s = limit_s;
  return p;
}

TEST(VirtualTrial, FixedSeedsAreReproducible) {
  const VirtualTrialResult a = run_virtual_trial(trial("CM1", 3));
  const VirtualTrialResult b = run_virtual_trial(trial("CM1", 3));
  EXPECT_EQ(a.hash, b.hash);
  EXPECT_EQ(a.ticks, b.ticks);
  EXPECT_EQ(a.metrics.falls, b.metrics.falls);
  EXPECT_EQ(a.metrics.time_total_s, b.metrics.time_total_s);
  EXPECT_EQ(a.metrics.time_out_s, b.metrics.time_out_s);
  VirtualTrialParams other = trial("CM1", 3);
  other.ffd.set("noise_seed", "77");
  EXPECT_NE(run_virtual_trial(other).hash, a.hash) << "another noise seed, another run";
}

TEST(VirtualTrial, PinsReachTheSubjectOnlyThroughTheTactileDevice) {
  // CM0 and CM1 give the same force; a subject that ignores the pins moves the same in both
  test::TempDir dir;
  const std::string blind = dir.file("blind.yaml");
  std::string text = test::read_file(baseline());
  const std::string use = "tactile_use: 1.0";
  ASSERT_NE(text.find(use), std::string::npos);
  test::write_file(blind, text.replace(text.find(use), use.size(), "tactile_use: 0"));
  EXPECT_EQ(run_virtual_trial(trial("CM0", 2, blind)).hash, run_virtual_trial(trial("CM1", 2, blind)).hash);
  // one that reads them does not
  EXPECT_NE(run_virtual_trial(trial("CM0", 2)).hash, run_virtual_trial(trial("CM1", 2)).hash);
}

TEST(VirtualTrial, CompletesTheBridgeAndFallsLessWithPins) {
  int completed_cm1 = 0, falls_cm0 = 0, falls_cm1 = 0;
  double out_cm0 = 0.0, out_cm1 = 0.0;
  constexpr int kSubjects = 8;
  for (int s = 1; s <= kSubjects; ++s) {
    const VirtualTrialResult cm0 = run_virtual_trial(trial("CM0", s));
    const VirtualTrialResult cm1 = run_virtual_trial(trial("CM1", s));
    completed_cm1 += cm1.metrics.completed;
    falls_cm0 += cm0.metrics.falls;
    falls_cm1 += cm1.metrics.falls;
    out_cm0 += cm0.metrics.time_out_s;
    out_cm1 += cm1.metrics.time_out_s;
  }
  EXPECT_GE(completed_cm1, kSubjects - 1);
  EXPECT_GT(falls_cm0, 0) << "without pins it falls sometimes";
  EXPECT_LT(falls_cm1, falls_cm0);
  EXPECT_LT(out_cm1, out_cm0);
}

TEST(VirtualTrial, LimitStopsATrial) {
  const VirtualTrialResult r = run_virtual_trial(trial("CM1", 1, baseline(), 2.0));
  EXPECT_FALSE(r.metrics.completed);
  EXPECT_EQ(r.ticks, 10'000);
  EXPECT_NEAR(r.metrics.time_total_s, 2.0, 1e-3);
}

// the simulated clock of the tick below
std::int64_t g_clock_ns = 0;
std::int64_t fake_clock() { return g_clock_ns; }

TEST(VirtualTrial, TickWithASubjectAllocatesNothing) {
  VirtualTrialParams p = trial("CM1", 1);
  sim::SimParams sp = graph::sim_params(p.sim);
  sim::Simulator simulator;
  simulator.configure(sp);
  auto force = graph::make_force_device(p.ffd);
  auto tactile = graph::make_tactile_device(p.tactile);
  graph::ColocatedLoop loop(simulator, *force, tactile.get(), &fake_clock);
  loop.activate();
  constexpr std::int64_t kPeriod = 200'000;
  for (std::int64_t n = 0; n < 100; ++n) loop.tick(g_clock_ns = n * kPeriod);
  std::size_t allocations = 0;
  int on_top = 0;
  {
    test::AllocGuard guard;
    for (std::int64_t n = 100; n < 25'000; ++n) on_top += loop.tick(g_clock_ns = n * kPeriod).step.on_top;
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(on_top, 10'000) << "the subject was on the bridge, pins and all";
}

}  // namespace
}  // namespace enact::experiment
