// The task on an object that is not a path (launch/scenes/ridge.yaml: a height map with a
// rounded crest curving in an S, its task line given in the scene): the scripted path counts
// the same fall as on the bridge, and "on top" is the crest's top, not the floor beside it.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>

#include "core/sim/offline.h"
#include "core/sim/simulator.h"
#include "tests/support/test_util.h"

namespace enact::sim {
namespace {

SimParams ridge(const std::string& model = "CM1") {
  SimParams p;
  p.scene = test::source_path("launch/scenes/ridge.yaml");
  p.model = model;
  return p;
}

TEST(TaskOnAnyObject, TheRidgesScriptedPathFallsOnceAndCompletes) {
  Simulator sim;
  sim.configure(ridge());
  ASSERT_TRUE(sim.has_task());
  const RunSummary s = run_offline(sim, scripted_path(sim), nullptr);
  // the path's two slides off the side: one under 1 s (not a fall), one of about 2 s (a fall)
  EXPECT_EQ(s.metrics.falls, 1);
  EXPECT_TRUE(s.metrics.completed);
  EXPECT_GE(s.metrics.time_out_s, 1.5);
  EXPECT_LE(s.metrics.time_out_s, 2.5);
  EXPECT_EQ(s.faults, 0u);
  // its length is the crest's, x = 5 mm sin(pi y / 22 mm) over 44 mm of y: 49.16 mm by
  // quadrature, 49.13 mm along the 22 chords the scene gives
  EXPECT_NEAR(sim.path().length_m(), 0.04913, 0.00002);
}

// the device held still for 0.1 s at x, y, z: the last step's output
StepOutput held_at(Simulator& sim, const math::Vec3& x) {
  sim.activate(0);
  StepOutput out;
  for (int n = 0; n < 500; ++n) out = sim.step(n * 200'000LL, x);
  return out;
}

TEST(TaskOnAnyObject, OnTheRoundedCrestALineOfMassesTouchesAndOnlyThereIsOnTop) {
  // pressed 0.5 mm into the crest at its middle (x = 0, y = 0, the crest 10 mm high): a
  // rounded top of 6 mm radius drops 1.26 mm at the grid's outer columns, so only the masses
  // near the crest line touch, and the pins show that line
  Simulator crest;
  crest.configure(ridge());
  const StepOutput on = held_at(crest, {0.0, 0.0, 0.0095});
  EXPECT_TRUE(on.on_top);
  EXPECT_GE(on.contacts, 2);
  EXPECT_LE(on.contacts, 10) << "a flat top would take all 16";
  EXPECT_EQ(std::popcount(on.pins), on.contacts) << "CM1: a pin up for each mass in contact";

  // 12 mm to the side, pressed 0.2 mm into the floor (the height map's flat surround lies
  // 0.5 mm under it): in contact, not on top
  Simulator floor;
  floor.configure(ridge());
  const StepOutput beside = held_at(floor, {0.012, 0.0, -0.0002});
  EXPECT_GT(beside.contacts, 0);
  EXPECT_FALSE(beside.on_top);
}

}  // namespace
}  // namespace enact::sim
