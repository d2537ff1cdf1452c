// The trial metrics at the edges of the 1 s rule, end to end: hand-made device paths through
// the simulator (physics, contact with the top, the bridge task), with answers known by
// construction: the body is lifted 2 mm off the top and put back at chosen times.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "core/sim/offline.h"
#include "tests/support/test_util.h"

namespace enact::sim {
namespace {

// on the top (pressing 0.05 mm in) or 2 mm above it, at the start of the bridge
constexpr double kX = -0.0074246, kY = -0.0222739;
constexpr double kOnZ = 0.012 - 0.00005, kOffZ = 0.014;

// a path that is on the top except over the given [from, to) intervals, until end_s; each
// change is a step between two samples 1 us apart, so every 200 us step sees one or the other
task::Trajectory path(const std::vector<std::pair<double, double>>& off, double end_s) {
  task::Trajectory t;
  auto add = [&](double time, bool on) {
    t.t_s.push_back(time);
    t.position_m.push_back({kX, kY, on ? kOnZ : kOffZ});
  };
  add(0.0, true);
  for (const auto& [from, to] : off) {
    add(from - 1e-6, true);
    add(from, false);
    add(to - 1e-6, false);
    add(to, true);
  }
  add(end_s, true);
  return t;
}

task::Metrics run(const task::Trajectory& t) {
  Simulator sim;
  SimParams p;
  p.scene = test::source_path("launch/scenes/bridge.yaml");
  p.model = "CM1";
  sim.configure(p);
  return run_offline(sim, t, nullptr).metrics;
}

TEST(MetricsEdges, ContactLostFor990msIsNotAFall) {
  const task::Metrics m = run(path({{1.0, 1.99}}, 4.0));
  EXPECT_EQ(m.falls, 0);
  EXPECT_EQ(m.time_out_s, 0.0);
  EXPECT_NEAR(m.time_total_s, 4.0, 1e-9);
  EXPECT_EQ(m.ratio, 0.0);
}

TEST(MetricsEdges, ContactLostFor1010msIsOneFallOf1010ms) {
  const task::Metrics m = run(path({{1.0, 2.01}}, 4.0));
  EXPECT_EQ(m.falls, 1);
  EXPECT_NEAR(m.time_out_s, 1.01, 1e-9);
  EXPECT_NEAR(m.time_total_s, 4.0, 1e-9);
  EXPECT_NEAR(m.ratio, 1.01 / 4.0, 1e-9);
}

TEST(MetricsEdges, ContactRegainedFor500msInsideAFallDoesNotEndIt) {
  // off 1-3 s, on 3-3.5 s, off 3.5-5 s, on from 5 s: one fall of 4 s
  const task::Metrics m = run(path({{1.0, 3.0}, {3.5, 5.0}}, 7.0));
  EXPECT_EQ(m.falls, 1);
  EXPECT_NEAR(m.time_out_s, 4.0, 1e-9);
  EXPECT_NEAR(m.ratio, 4.0 / 7.0, 1e-9);
}

TEST(MetricsEdges, TwoSeparateFallsCountTwice) {
  // the same losses with 1.5 s of contact between them: two falls, 3.5 s out
  const task::Metrics m = run(path({{1.0, 3.0}, {4.5, 6.0}}, 8.0));
  EXPECT_EQ(m.falls, 2);
  EXPECT_NEAR(m.time_out_s, 3.5, 1e-9);
}

}  // namespace
}  // namespace enact::sim
