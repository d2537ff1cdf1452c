// The simulated force device: still when nothing pushes it, F/m under a constant command,
// saturation at the peak force, the workspace stops, a hand tracking a path, determinism,
// refused params and no allocation in the loop.
#include "core/devices/simulated_force.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/config/yaml.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/test_util.h"

namespace enact::devices {
namespace {

using math::Vec3;

using test::kMs;
constexpr std::int64_t kUs = 1'000;

SimulatedForceParams free_device() {
  SimulatedForceParams p;
  p.hand_stiffness_n_per_m = 0.0;
  p.hand_damping_n_s_per_m = 0.0;
  return p;
}

SimulatedForceDevice started(const SimulatedForceParams& p) {
  SimulatedForceDevice d(p);
  d.configure();
  d.activate();
  return d;
}

// exact speed of m v' = F - b v from rest
double exact_speed(double force_n, double mass_kg, double damping, double t_s) {
  return force_n / damping * (1.0 - std::exp(-damping * t_s / mass_kg));
}

double axis(const Vec3& v, int i) { return i == 0 ? v.x : i == 1 ? v.y : v.z; }

void expect_error_with_fix(const SimulatedForceParams& p, const std::string& needle) {
  SimulatedForceDevice d(p);
  try {
    d.configure();
    ADD_FAILURE() << "no error for " << needle;
  } catch (const config::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(needle), std::string::npos) << what;
    EXPECT_NE(what.find("fix:"), std::string::npos) << what;
  }
}

TEST(SimulatedForce, StaysStillAndReportsTheStartQuantised) {
  SimulatedForceParams p;
  p.start_m = {0.0123456, -0.0045674, 0.0100004};
  SimulatedForceDevice d = started(p);
  ForceSample s;
  for (std::int64_t t = 0; t <= 1000 * kMs; t += 200 * kUs) {
    ASSERT_TRUE(d.read(t, s));
    d.write(t, {});
    EXPECT_LT(norm(d.true_position_m() - p.start_m), 1e-9);
  }
  // ERGOS resolution 1 um: rounded to the nearest micrometre
  EXPECT_EQ(s.time_ns, 1000 * kMs);
  EXPECT_NEAR(s.position_m.x, 0.012346, 1e-12);
  EXPECT_NEAR(s.position_m.y, -0.004567, 1e-12);
  EXPECT_NEAR(s.position_m.z, 0.010000, 1e-12);
  EXPECT_EQ(s.faults, 0u);
  EXPECT_EQ(norm(s.velocity_m_per_s), 0.0);
}

TEST(SimulatedForce, ReadIsRefusedWhenNotActive) {
  SimulatedForceDevice d;
  d.configure();
  ForceSample s;
  EXPECT_FALSE(d.read(0, s));
  EXPECT_TRUE(has(s.faults, DeviceFault::device_error));
  d.activate();
  EXPECT_TRUE(d.read(0, s));
  d.deactivate();
  EXPECT_FALSE(d.read(kMs, s));
}

TEST(SimulatedForce, ConstantCommandAcceleratesTheFreeDeviceAsFOverM) {
  SimulatedForceDevice d = started(free_device());
  const auto& profile = d.profile();
  const Vec3 force{3.0, -4.0, 12.0};  // |F| = 13 N
  ForceSample s;
  d.read(0, s);
  d.write(0, force);
  d.read(kMs, s);
  // m v' = F - b v along F: the exact solution, and about F/m t this early
  const double expected = exact_speed(13.0, profile.moving_mass_kg, profile.damping_n_s_per_m, 1e-3);
  EXPECT_NEAR(norm(s.velocity_m_per_s), expected, 0.01 * expected);
  EXPECT_NEAR(expected, 13.0 / profile.moving_mass_kg * 1e-3, 0.02 * expected);
  EXPECT_LT(norm(s.velocity_m_per_s * (1.0 / norm(s.velocity_m_per_s)) - force * (1.0 / 13.0)), 1e-12);
  EXPECT_EQ(s.faults, 0u);
}

TEST(SimulatedForce, CommandOverThePeakIsSaturated) {
  SimulatedForceDevice d = started(free_device());
  const auto& profile = d.profile();
  ASSERT_DOUBLE_EQ(profile.peak_force_n, 200.0);
  ForceSample s;
  d.read(0, s);
  d.write(0, {300.0, 400.0, 0.0});  // 500 N
  EXPECT_LT(norm(d.applied_force_n() - Vec3{120.0, 160.0, 0.0}), 1e-12);
  d.read(kMs, s);
  const double expected = exact_speed(200.0, profile.moving_mass_kg, profile.damping_n_s_per_m, 1e-3);
  EXPECT_NEAR(norm(s.velocity_m_per_s), expected, 0.01 * expected);
  EXPECT_NEAR(s.velocity_m_per_s.x / s.velocity_m_per_s.y, 0.75, 1e-12);
  EXPECT_TRUE(has(s.faults, DeviceFault::clamped));
  // back under the peak: no longer clamped
  d.write(kMs, {1.0, 0.0, 0.0});
  d.read(2 * kMs, s);
  EXPECT_FALSE(has(s.faults, DeviceFault::clamped));
}

TEST(SimulatedForce, NonfiniteCommandGivesNoForce) {
  SimulatedForceDevice d = started(free_device());
  ForceSample s;
  d.read(0, s);
  d.write(0, {std::nan(""), 1.0, 0.0});
  d.read(kMs, s);
  EXPECT_EQ(norm(s.velocity_m_per_s), 0.0);
  EXPECT_TRUE(has(s.faults, DeviceFault::nonfinite_command));
}

// pushed at the peak force into a stop, arriving at the max speed: the stop is critically
// damped (and the device adds its own damping), so it settles at the static penetration
// F / k_stop without a noticeable overshoot (tolerance 10 um)
TEST(SimulatedForce, WorkspaceStopHoldsTheDevice) {
  struct Push { Vec3 direction; int axis; double sign; };
  const std::vector<Push> pushes = {{{1, 0, 0}, 0, 1.0}, {{0, -1, 0}, 1, -1.0}, {{0, 0, -1}, 2, -1.0}};
  const SimulatedForceParams p = free_device();
  for (const Push& push : pushes) {
    SimulatedForceDevice d = started(p);
    const auto& profile = d.profile();
    const double force = profile.peak_force_n;
    const double limit = push.sign > 0 ? axis(profile.workspace_max_m, push.axis) : axis(profile.workspace_min_m, push.axis);
    const double static_m = force / p.stop_stiffness_n_per_m;
    ForceSample s;
    double worst_m = 0.0;
    bool flagged = false;
    for (std::int64_t t = 0; t <= 300 * kMs; t += 200 * kUs) {
      d.read(t, s);
      d.write(t, push.direction * force);
      const double beyond = push.sign * (axis(d.true_position_m(), push.axis) - limit);
      worst_m = std::max(worst_m, beyond);
      EXPECT_EQ(beyond > 0.0, has(s.faults, DeviceFault::workspace_limit)) << t;
      flagged = flagged || has(s.faults, DeviceFault::workspace_limit);
    }
    EXPECT_TRUE(flagged);
    EXPECT_LE(worst_m, static_m + 1e-5);
    const double settled = push.sign * (axis(d.true_position_m(), push.axis) - limit);
    EXPECT_NEAR(settled, static_m, 1e-7);
    EXPECT_GT(d.speed_clamps(), 0u);  // the approach ran at the max speed
  }
}

// the hand path: holds 0.2 s, moves 1 cm along x at u = 1 cm/s, holds. Once settled the end-
// effector lags the target by b u / k_hand (the device's damping drag held by the hand's
// spring; the hand's own damping acts on the relative velocity), and catches up at the end
TEST(SimulatedForce, HandTracksAPath) {
  test::TempDir dir;
  const std::string path = dir.file("hand.csv");
  test::write_file(path, "t_s,x_m,y_m,z_m\n0,0,0,0.0125\n0.2,0,0,0.0125\n1.2,0.01,0,0.0125\n2,0.01,0,0.0125\n");
  SimulatedForceParams p;
  p.hand_path = path;
  SimulatedForceDevice d = started(p);
  const double u = 0.01;
  const double lag_m = d.profile().damping_n_s_per_m * u / p.hand_stiffness_n_per_m;
  const double quantum_m = d.profile().resolution_m;
  ForceSample s;
  int checked = 0;
  for (std::int64_t t = 0; t <= 2000 * kMs; t += kMs) {
    d.read(t, s);
    d.write(t, {});
    const double t_s = static_cast<double>(t) * 1e-9;
    const Vec3 target = d.hand_target_m();
    if (t_s >= 0.2 && t_s <= 1.2) {
      EXPECT_NEAR(target.x, u * (t_s - 0.2), 1e-12);
    }
    const double error = norm(s.position_m - target);
    if (t_s >= 0.5 && t_s <= 1.2) {
      EXPECT_LE(error, 1.02 * lag_m + quantum_m) << t_s;
      EXPECT_GE(error, 0.98 * lag_m - quantum_m) << t_s;
      EXPECT_LT(s.position_m.x, target.x);  // behind, not ahead
      ++checked;
    }
    if (t_s >= 1.7) {
      EXPECT_LE(error, 2.0 * quantum_m) << t_s;
    }
  }
  EXPECT_GT(checked, 600);
}

void expect_same(const ForceSample& a, const ForceSample& b) {
  EXPECT_EQ(a.time_ns, b.time_ns);
  EXPECT_EQ(a.position_m, b.position_m);
  EXPECT_EQ(a.velocity_m_per_s, b.velocity_m_per_s);
  EXPECT_EQ(a.buttons, b.buttons);
  EXPECT_EQ(a.faults, b.faults);
}

TEST(SimulatedForce, SameCallsGiveIdenticalSamples) {
  test::TempDir dir;
  const std::string path = dir.file("hand.csv");
  test::write_file(path, "t_s,x_m,y_m,z_m\n0,0,0,0.0125\n0.1,0.02,0.01,0.02\n0.2,-0.02,0.0,0.005\n");
  SimulatedForceParams p;
  p.hand_path = path;
  SimulatedForceDevice a = started(p);
  SimulatedForceDevice b = started(p);
  ForceSample sa, sb;
  std::int64_t t = 5 * kMs;
  for (int i = 0; i < 2000; ++i) {
    t += 50 * kUs + (i * 37 % 300) * kUs;  // irregular periods
    const Vec3 force{40.0 * std::sin(i * 0.01), 250.0 * std::cos(i * 0.003), -5.0};
    a.read(t, sa);
    b.read(t, sb);
    expect_same(sa, sb);
    a.write(t, force);
    b.write(t, force);
  }
  EXPECT_GT(norm(a.true_position_m() - p.start_m), 1e-3);  // it did move
}

TEST(SimulatedForce, BadParamsAreRefusedWithAFix) {
  SimulatedForceParams p;
  p.profile = "phantom";
  expect_error_with_fix(p, "ergos");
  expect_error_with_fix(p, "falcon");
  p = {};
  p.hand_stiffness_n_per_m = -1.0;
  expect_error_with_fix(p, "hand_stiffness_n_per_m");
  p = {};
  p.hand_damping_n_s_per_m = std::nan("");
  expect_error_with_fix(p, "hand_damping_n_s_per_m");
  p = {};
  p.stop_stiffness_n_per_m = 0.0;
  expect_error_with_fix(p, "stop_stiffness_n_per_m");
  p = {};
  p.substep_s = 0.0;
  expect_error_with_fix(p, "substep_s");
  p = {};
  p.substep_s = 1e-3;  // too long for the 1e5 N/m stop
  expect_error_with_fix(p, "substep_s");
  p = {};
  p.start_m = {0.0, 0.0, 0.1};
  expect_error_with_fix(p, "start_m");
  p = {};
  p.hand_path = "/nonexistent/hand.csv";
  expect_error_with_fix(p, "/nonexistent/hand.csv");
  // a free device (no hand) is fine
  SimulatedForceDevice ok(free_device());
  EXPECT_NO_THROW(ok.configure());
  EXPECT_GE(ok.max_substep_s(), ok.params().substep_s);
}

TEST(SimulatedForce, ReadAndWriteAllocateNothing) {
  test::TempDir dir;
  const std::string path = dir.file("hand.csv");
  test::write_file(path, "t_s,x_m,y_m,z_m\n0,0,0,0.0125\n0.5,0.04,0,0.0125\n1,0,0,0.0125\n");
  SimulatedForceParams p;
  p.hand_path = path;
  SimulatedForceDevice d = started(p);
  std::vector<int> v;
  std::size_t counted = 0;
  std::size_t allocations = 0;
  {
    test::AllocGuard guard;
    v.push_back(1);
    counted = guard.allocations();
  }
  ForceSample s;
  double max_x_m = 0.0;
  {
    test::AllocGuard guard;
    for (std::int64_t t = 0; t <= 1000 * kMs; t += 200 * kUs) {
      d.read(t, s);
      max_x_m = std::max(max_x_m, d.true_position_m().x);
      d.write(t, {300.0 * std::sin(static_cast<double>(t) * 1e-8), std::nan(""), 0.0});
      d.write(t, {0.0, -0.5 * s.velocity_m_per_s.y, 2.0});
    }
    allocations = guard.allocations();
  }
  asm volatile("" : : "g"(v.data()) : "memory");
  EXPECT_GT(counted, 0u);  // the guard counts
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(max_x_m, d.profile().workspace_max_m.x);  // the hand pulled it into the stop
}

}  // namespace
}  // namespace enact::devices
