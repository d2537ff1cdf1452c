#include "core/sim/offline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/physics/scene.h"
#include "tests/sim/sim_test_util.h"
#include "tests/support/test_util.h"

namespace enact::sim {
namespace {

using test_util::bridge;

// one step's output, kept from a run
struct Row {
  double force_n;
  int contacts;
  std::uint32_t pins;
  bool on_top;
};

struct ScriptedRun {
  RunSummary summary;
  std::vector<Row> rows;
};

// the scripted path through the bridge, stepping by hand to keep every output
ScriptedRun run_scripted(const std::string& model, double rate_hz = 0.0) {
  Simulator sim;
  sim.configure(bridge(model, rate_hz));
  const task::Trajectory tr = scripted_path(sim);
  ScriptedRun run;
  sim.activate(0);
  const double dt = sim.model().dt_s;
  for (double t = 0.0; t <= tr.end_s(); t = static_cast<double>(run.rows.size()) * dt) {
    const StepOutput& o = sim.step(std::llround(t * 1e9), tr.at(t));
    run.rows.push_back({math::norm(o.force_n), o.contacts, o.pins, o.on_top});
  }
  run.summary.metrics = sim.metrics();
  return run;
}

TEST(ScriptedPath, OneFallCompletedForCM1) {
  Simulator sim;
  sim.configure(bridge("CM1"));
  const RunSummary s = run_offline(sim, scripted_path(sim), nullptr);
  EXPECT_EQ(s.metrics.falls, 1);
  EXPECT_TRUE(s.metrics.completed);
  EXPECT_GE(s.metrics.time_out_s, 1.5);
  EXPECT_LE(s.metrics.time_out_s, 2.5);
  EXPECT_GT(s.metrics.time_total_s, s.metrics.time_out_s);
  EXPECT_NEAR(s.metrics.ratio, s.metrics.time_out_s / s.metrics.time_total_s, 1e-12);
  EXPECT_EQ(s.faults, 0u);
}

// a scripted hand whose path never comes near the scene is warned about, with the fix
TEST(HandPath, APathThatNeverReachesTheSceneIsWarnedAbout) {
  const std::string walk = test::source_path("launch/paths/bridge_walk.csv");
  EXPECT_EQ(hand_path_warning(test::source_path("launch/scenes/bridge.yaml"), walk), "");
  EXPECT_EQ(hand_path_warning(test::source_path("launch/scenes/ridge.yaml"), walk), "");
  // a grating of three bars 40 mm beside the walk, on a floor the walk stays 6 mm above
  const test::TempDir dir;
  const std::string grating = dir.file("grating.yaml");
  test::write_file(grating, R"(scene: grating
rate_hz: 5000
objects:
  - {name: bars, type: union, boxes: [{center_m: [0.05, 0, 0.001], half_extents_m: [0.001, 0.02, 0.001]}, {center_m: [0.054, 0, 0.001], half_extents_m: [0.001, 0.02, 0.001]}]}
  - {name: floor, type: plane, point_m: [0, 0, 0], normal: [0, 0, 1]}
body:
  name: finger
  position_m: [0.05, 0, 0.004]
  grid: {rows: 4, cols: 4, pitch_m: 0.00245}
contacts:
  - {masses: body, objects: [bars, floor], stiffness_n_per_m: 3000, damping_n_s_per_m: 0.01}
)");
  const std::string warning = hand_path_warning(grating, walk);
  EXPECT_NE(warning.find("never comes near the scene " + grating), std::string::npos) << warning;
  EXPECT_NE(warning.find("fix: give a path that reaches the scene: --arg hand_path="), std::string::npos) << warning;
  // the same walk 5 mm lower reaches the floor
  task::Trajectory low = task::load_trajectory(walk);
  for (math::Vec3& p : low.position_m) p.z -= 0.005;
  EXPECT_TRUE(path_may_touch(physics::load_scene(grating), low));
  // a scene with a task: its own path is the fix
  task::Trajectory far = task::load_trajectory(walk);
  for (math::Vec3& p : far.position_m) p.z += 0.05;
  const std::string far_walk = dir.file("far.csv");
  {
    std::ofstream out(far_walk);
    task::write_trajectory(far, out);
  }
  const std::string bridge_scene = test::source_path("launch/scenes/bridge.yaml");
  EXPECT_NE(hand_path_warning(bridge_scene, far_walk).find("fix: the scene's own path: enact path " + bridge_scene + " -o path.csv"), std::string::npos)
      << hand_path_warning(bridge_scene, far_walk);
}

// a run that does not complete says why: the path passed the end off the top, or stopped short
TEST(ScriptedPath, ARunNotDoneSaysWhy) {
  Simulator sim;
  sim.configure(bridge("CM1"));
  const task::Trajectory scripted = scripted_path(sim);
  EXPECT_EQ(not_done_reason(run_offline(sim, scripted, nullptr), sim), "");

  task::Trajectory above = scripted;  // the same walk, 5 mm above the top: never on it
  for (math::Vec3& p : above.position_m) p.z += 0.005;
  const RunSummary off = run_offline(sim, above, nullptr);
  ASSERT_FALSE(off.metrics.completed);
  EXPECT_GE(off.path_progress, 0.98);
  const std::string why = not_done_reason(off, sim);
  EXPECT_NE(why.find("not done (CM1): progress along the path reached 1.00, but on the top of 'bridge' only 0.00"), std::string::npos) << why;

  task::Trajectory half;  // the first half of the walk, on the top
  for (std::size_t i = 0; i < scripted.t_s.size() / 2; ++i) {
    half.t_s.push_back(scripted.t_s[i]);
    half.position_m.push_back(scripted.position_m[i]);
  }
  const RunSummary short_run = run_offline(sim, half, nullptr);
  ASSERT_FALSE(short_run.metrics.completed);
  const std::string short_why = not_done_reason(short_run, sim);
  EXPECT_NE(short_why.find("not done (CM1): the path ends at progress"), std::string::npos) << short_why;
}

// the step-by-step runs below see the same trial as run_offline
TEST(ScriptedPath, ManualSteppingMatchesRunOffline) {
  Simulator sim;
  sim.configure(bridge("CM1"));
  const task::Metrics offline = run_offline(sim, scripted_path(sim), nullptr).metrics;
  const task::Metrics manual = run_scripted("CM1").summary.metrics;
  EXPECT_EQ(manual.falls, offline.falls);
  EXPECT_EQ(manual.completed, offline.completed);
  EXPECT_DOUBLE_EQ(manual.time_out_s, offline.time_out_s);
  EXPECT_DOUBLE_EQ(manual.time_total_s, offline.time_total_s);
}

TEST(ScriptedPath, CM1ForceIsNonzeroWhileOnTop) {
  const ScriptedRun run = run_scripted("CM1");
  int on_top = 0, zero_on_top = 0;
  for (const Row& r : run.rows) {
    on_top += r.on_top;
    zero_on_top += r.on_top && r.force_n == 0.0;
  }
  EXPECT_GT(on_top, static_cast<int>(run.rows.size()) / 2);
  EXPECT_EQ(zero_on_top, 0);
}

TEST(ScriptedPath, TGivesNoForceButPins) {
  const ScriptedRun run = run_scripted("T");
  int on_top = 0, pins_up = 0;
  for (const Row& r : run.rows) {
    EXPECT_EQ(r.force_n, 0.0);
    on_top += r.on_top;
    pins_up += r.pins != 0;
  }
  EXPECT_GT(on_top, 0);
  EXPECT_GT(pins_up, 0);
}

TEST(ScriptedPath, CM2RaisesPinsWhileForceIsZero) {
  // the path presses 0.1 mm, below CM2's 3 mm threshold: touch without force
  const ScriptedRun run = run_scripted("CM2");
  int pins_up = 0;
  for (const Row& r : run.rows) {
    EXPECT_EQ(r.force_n, 0.0);
    if (r.pins == 0) continue;
    ++pins_up;
    EXPECT_GT(r.contacts, 0);
  }
  EXPECT_GT(pins_up, static_cast<int>(run.rows.size()) / 2);
}

TEST(ScriptedPath, NotOnTopWhenNoGridMassTouches) {
  const ScriptedRun run = run_scripted("CM1");
  int untouched = 0;
  for (const Row& r : run.rows) {
    if (r.contacts != 0) continue;
    ++untouched;
    EXPECT_FALSE(r.on_top);
  }
  EXPECT_GT(untouched, 0);  // the path does leave the top
}

std::string csv_of(const std::string& model, double rate_hz = 0.0) {
  Simulator sim;
  sim.configure(bridge(model, rate_hz));
  std::ostringstream out;
  run_offline(sim, scripted_path(sim), &out);
  return out.str();
}

TEST(RunOffline, IsDeterministic) {
  const std::string a = csv_of("CM1");
  const std::string b = csv_of("CM1");
  EXPECT_GT(a.size(), 1000u);
  EXPECT_TRUE(a == b);
  EXPECT_NE(a, csv_of("CM3"));  // the output depends on the model: the comparison is not vacuous
}

TEST(RunOffline, CsvHasOneRowPerStep) {
  Simulator sim;
  sim.configure(bridge("CM1"));
  std::ostringstream out;
  const RunSummary s = run_offline(sim, scripted_path(sim), &out);
  const std::string csv = out.str();
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "t_s,x_m,y_m,z_m,fx_n,fy_n,fz_n,contacts,pins,on_top,progress,fault");
  std::int64_t lines = 0;
  for (char c : csv) lines += c == '\n';
  EXPECT_EQ(lines, s.steps + 1);
}

TEST(RunOffline, MetricsAreRateIndependent) {
  const double rates[] = {1000.0, 5000.0, 20000.0};
  std::vector<task::Metrics> m;
  for (double rate : rates) {
    Simulator sim;
    sim.configure(bridge("CM1", rate));
    m.push_back(run_offline(sim, scripted_path(sim), nullptr).metrics);
  }
  for (std::size_t i = 1; i < m.size(); ++i) {
    SCOPED_TRACE(rates[i]);
    EXPECT_EQ(m[i].falls, m[0].falls);
    EXPECT_EQ(m[i].completed, m[0].completed);
    EXPECT_NEAR(m[i].time_out_s, m[0].time_out_s, 0.002);
    EXPECT_NEAR(m[i].time_total_s, m[0].time_total_s, 0.002);
  }
  EXPECT_EQ(m[0].falls, 1);
}

TEST(Trajectory, InterpolatesAndClamps) {
  task::Trajectory tr;
  tr.t_s = {1.0, 2.0};
  tr.position_m = {{0, 0, 0}, {2, 4, 6}};
  EXPECT_DOUBLE_EQ(tr.at(1.5).y, 2.0);
  EXPECT_DOUBLE_EQ(tr.at(0.0).z, 0.0);
  EXPECT_DOUBLE_EQ(tr.at(9.0).z, 6.0);
}

TEST(Trajectory, WriteThenLoadRoundTrips) {
  Simulator sim;
  sim.configure(bridge());
  const task::Trajectory tr = scripted_path(sim);
  const test::TempDir dir;
  std::ostringstream out;
  task::write_trajectory(tr, out);
  test::write_file(dir.file("path.csv"), out.str());
  const task::Trajectory back = task::load_trajectory(dir.file("path.csv"));
  ASSERT_EQ(back.t_s.size(), tr.t_s.size());
  for (std::size_t i = 0; i < tr.t_s.size(); ++i) {
    EXPECT_NEAR(back.t_s[i], tr.t_s[i], 1e-9);
    EXPECT_NEAR(back.position_m[i].x, tr.position_m[i].x, 1e-9);
  }
}

}  // namespace
}  // namespace enact::sim
