// The explicit stability bound K + 2Z < 4M is sharp: just below it a mass on a spring stays
// bounded for 10^6 steps; just above it the load-time analysis refuses the scene with the
// right numbers and, run anyway, the divergence guard trips cleanly. implicit_euler is
// unconditionally stable; the device passivity bound sums all 16 grid contacts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <tuple>

#include "core/physics/stability.h"
#include "tests/physics/models.h"

namespace enact::physics {
namespace {

constexpr double kMass_kg = 0.01;
constexpr double kRate_hz = 1000.0;
constexpr double kDt_s = 1.0 / kRate_hz;
constexpr double kM = kMass_kg / (kDt_s * kDt_s);  // M = m / dt^2 (N/m)
constexpr double kX0_m = 0.001;

std::string g4(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// integrator, and damping as a fraction of M (Z = z / dt = fraction * M)
class ExplicitBound : public ::testing::TestWithParam<std::tuple<Integrator, double>> {
 protected:
  Integrator integrator() const { return std::get<0>(GetParam()); }
  double damping_n_s_per_m() const { return std::get<1>(GetParam()) * kM * kDt_s; }
  // the largest stable stiffness: K + 2Z < 4M
  double bound_n_per_m() const { return 4.0 * kM - 2.0 * damping_n_s_per_m() / kDt_s; }
  models::Oscillator at(double fraction_of_bound, PointKind anchor = PointKind::fixed) const {
    return models::oscillator(integrator(), kRate_hz, kMass_kg, fraction_of_bound * bound_n_per_m(), damping_n_s_per_m(), kX0_m, anchor);
  }
};

TEST_P(ExplicitBound, JustBelowTheBoundStaysBoundedForAMillionSteps) {
  const models::Oscillator o = at(0.99);
  EXPECT_TRUE(analyze_stability(o.model).stable());
  State s = make_state(o.model);
  double max_all = 0.0, max_first = 0.0, max_last = 0.0;
  constexpr int kSteps = 1'000'000, kWindow = 10'000;
  for (int n = 0; n < kSteps; ++n) {
    step(o.model, s);
    const double x = std::abs(s.x[o.mass].x);
    max_all = std::max(max_all, x);
    if (n < kWindow) max_first = std::max(max_first, x);
    if (n >= kSteps - kWindow) max_last = std::max(max_last, x);
  }
  EXPECT_EQ(s.faults, 0u);
  EXPECT_TRUE(finite(s.x[o.mass]));
  // near the bound the oscillation sits at the Nyquist rate; by the recurrence's invariant,
  // cordis (second-order start) keeps the amplitude x0, symplectic Euler started from rest
  // reaches x0 / sqrt(1 - K / 4M) = 10 x0 (damping only lowers both)
  const double amplitude = integrator() == Integrator::cordis ? kX0_m : 10.0 * kX0_m;
  EXPECT_LE(max_all, amplitude * (1.0 + 1e-6));
  EXPECT_LE(max_last, max_first * (1.0 + 1e-6)) << "the amplitude grows";
}

TEST_P(ExplicitBound, JustAboveTheBoundIsRefusedWithTheLargestStableStiffness) {
  const models::Oscillator o = at(1.01);
  const StabilityReport report = analyze_stability(o.model);
  ASSERT_FALSE(report.stable());
  ASSERT_EQ(report.masses.size(), 1u);
  const MassStability& ms = report.masses[0];
  EXPECT_NEAR(ms.limit, 4.0 * kM, 1e-9 * 4.0 * kM);
  EXPECT_NEAR(ms.largest_stable_stiffness_n_per_m, bound_n_per_m(), 1e-9 * bound_n_per_m());
  EXPECT_LE(ms.largest_stable_stiffness_n_per_m + 2.0 * damping_n_s_per_m() / kDt_s, ms.limit * (1.0 + 1e-12));
  const std::string message = instability_message(o.model, report);
  EXPECT_NE(message.find("oscillator.yaml:"), std::string::npos) << message;
  EXPECT_NE(message.find("link 'spring'"), std::string::npos) << message;
  EXPECT_NE(message.find("4M = " + g4(4.0 * kM)), std::string::npos) << message;
  EXPECT_NE(message.find("below " + g4(bound_n_per_m())), std::string::npos) << message;
  // the advertised stiffness is the supremum: a hair below it is stable, a hair above is not
  EXPECT_TRUE(analyze_stability(at(1.0 - 1e-6).model).stable());
  EXPECT_FALSE(analyze_stability(at(1.0 + 1e-6).model).stable());
}

TEST_P(ExplicitBound, JustAboveTheBoundTripsTheGuardWithoutNaN) {
  const models::Oscillator o = at(1.01, PointKind::kinematic);
  State s = make_state(o.model);
  int trip_step = -1;
  Vec3 force_before_trip;
  for (int n = 0; n < 10'000; ++n) {
    const Vec3 previous_force = s.proxy_force_n[0];
    step(o.model, s);
    ASSERT_TRUE(models::state_finite(s)) << "step " << n;
    if (trip_step < 0 && s.faults > 0) {
      trip_step = n;
      force_before_trip = previous_force;
      EXPECT_TRUE(s.last_fault == Fault::runaway_position || s.last_fault == Fault::runaway_speed ||
                  s.last_fault == Fault::nonfinite_state)
          << to_string(s.last_fault);
      EXPECT_EQ(s.last_fault_point, o.mass);
      EXPECT_EQ(s.proxy_force_n[0], Vec3{}) << "the device must not feel a diverging force";
      EXPECT_EQ(s.x[o.mass], o.model.points[o.mass].position_m) << "the mass is reset";
    }
  }
  ASSERT_GE(trip_step, 0) << "the divergence guard never tripped";
  EXPECT_GT(norm(force_before_trip), 0.0) << "the spring fed the device before the trip";
}

INSTANTIATE_TEST_SUITE_P(Integrators, ExplicitBound,
                         ::testing::Combine(::testing::Values(Integrator::cordis, Integrator::symplectic_euler),
                                            ::testing::Values(0.0, 0.25)),
                         [](const auto& p) {
                           return std::string(to_string(std::get<0>(p.param))) +
                                  (std::get<1>(p.param) > 0.0 ? "_damped" : "_undamped");
                         });

TEST(ImplicitEuler, HundredTimesTheExplicitBoundStaysBounded) {
  for (const double z : {0.0, 0.25 * kM * kDt_s}) {
    SCOPED_TRACE(z);
    const models::Oscillator o = models::oscillator(Integrator::implicit_euler, kRate_hz, kMass_kg, 100.0 * 4.0 * kM, z, kX0_m);
    EXPECT_TRUE(analyze_stability(o.model).stable());
    State s = make_state(o.model);
    double max_x = 0.0;
    for (int n = 0; n < 1'000'000; ++n) {
      step(o.model, s);
      max_x = std::max(max_x, std::abs(s.x[o.mass].x));
    }
    EXPECT_EQ(s.faults, 0u);
    EXPECT_LE(max_x, kX0_m);
  }
}

// K and B of a device: every contact of every grid mass feeding it, all at once
void expect_passivity(const Model& m, double b, double k_sum, double z_sum) {
  const StabilityReport r = analyze_stability(m, b);
  ASSERT_EQ(r.devices.size(), 1u);
  const DevicePassivity& d = r.devices[0];
  EXPECT_EQ(d.stiffness_n_per_m, k_sum);
  EXPECT_EQ(d.damping_n_s_per_m, z_sum);
  EXPECT_EQ(d.required_n_s_per_m, k_sum * m.dt_s / 2.0 + z_sum);
  EXPECT_EQ(d.passive, b > k_sum * m.dt_s / 2.0 + z_sum);
}

TEST(DevicePassivity, SixteenGridContactsAddUp) {
  // binary-exact k and z so that the sums are exact
  constexpr double k = 3000.0, z = 0.03125;
  Model m;
  m.set_rate(5000.0);
  models::add_body(m, {0, 0, 0.0119});
  const int top = models::add_boxes(m, "table", {{{0, 0, 0.006}, {0.02, 0.02, 0.006}}});
  for (int i = 0; i < 16; ++i) models::add_contact(m, m.proxies[0].first_body + i, top, k, z);
  expect_passivity(m, 6.0, 16 * k, 16 * z);   // 4.8 + 0.5 < 6: passive
  m.set_rate(1000.0);
  expect_passivity(m, 6.0, 16 * k, 16 * z);   // 24 + 0.5 > 6: not passive
}

TEST(DevicePassivity, BridgeSceneCountsOnlyTheMassesFeedingTheDevice) {
  // bridge and floor are disjoint volumes: one contact per mass at a time; CM1 feeds the
  // 16 grid masses, P only the centre
  Model m = models::bridge(5000.0, "CM1");
  const double k = m.contacts[0].stiffness_n_per_m, z = m.contacts[0].damping_n_s_per_m;
  double z16 = 0.0;
  for (int i = 0; i < 16; ++i) z16 += z;
  expect_passivity(m, 6.0, 16 * k, z16);
  haptics::apply(*haptics::preset("P"), m);
  expect_passivity(m, 6.0, k, z);
}

}  // namespace
}  // namespace enact::physics
