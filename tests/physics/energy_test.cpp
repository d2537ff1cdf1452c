// Energy behaviour: the explicit symplectic schemes keep an undamped oscillator's energy
// without secular drift over 10^6 steps (implicit Euler, for contrast, loses it); damped
// contact never gains energy; a body resting on a surface with the hand still does not chatter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/physics/models.h"

namespace enact::physics {
namespace {

constexpr double kMass_kg = 0.01;
constexpr double kRate_hz = 5000.0;
constexpr double kDt_s = 1.0 / kRate_hz;

struct Drift {
  double first_mean_j = 0.0;  // mean energy over the first window
  double last_mean_j = 0.0;   // and over the last
  double relative() const { return std::abs(last_mean_j - first_mean_j) / first_mean_j; }
};

// an undamped 20 Hz oscillator over 10^6 steps; energy 1/2 m v^2 + 1/2 k x^2 at step n with the
// centred velocity (x(n+1) - x(n-1)) / 2dt, consistent with the position recurrence
Drift oscillator_energy(Integrator integrator) {
  const double w = 2.0 * models::kPi * 20.0, k = kMass_kg * w * w;
  const models::Oscillator o = models::oscillator(integrator, kRate_hz, kMass_kg, k, 0.0, 0.001);
  State s = make_state(o.model);
  constexpr int kSteps = 1'000'000, kWindow = 10'000;
  double before = s.x[o.mass].x - s.v[o.mass].x * kDt_s;  // x(-1) for the first centred velocity
  double now = s.x[o.mass].x;
  Drift d;
  for (int n = 0; n < kSteps; ++n) {
    step(o.model, s);
    const double after = s.x[o.mass].x;
    const double v = (after - before) / (2.0 * kDt_s);
    const double e = 0.5 * kMass_kg * v * v + 0.5 * k * now * now;
    if (n < kWindow) d.first_mean_j += e / kWindow;
    if (n >= kSteps - kWindow) d.last_mean_j += e / kWindow;
    before = now;
    now = after;
  }
  EXPECT_EQ(s.faults, 0u);
  return d;
}

TEST(Energy, CordisHasNoSecularDrift) {
  const Drift d = oscillator_energy(Integrator::cordis);
  EXPECT_LT(d.relative(), 1e-6) << d.first_mean_j << " -> " << d.last_mean_j;
}

TEST(Energy, SymplecticEulerHasNoSecularDrift) {
  const Drift d = oscillator_energy(Integrator::symplectic_euler);
  EXPECT_LT(d.relative(), 1e-6) << d.first_mean_j << " -> " << d.last_mean_j;
}

// the same measure detects a non-symplectic scheme: implicit Euler dissipates
TEST(Energy, ImplicitEulerLosesEnergy) {
  const Drift d = oscillator_energy(Integrator::implicit_euler);
  EXPECT_LT(d.last_mean_j, 0.99 * d.first_mean_j) << d.first_mean_j << " -> " << d.last_mean_j;
}

// a mass dropped from rest onto a damped plane under gravity: its total mechanical energy
// (kinetic + gravity + contact spring) after the first impact never exceeds m g h0
class DampedContact : public ::testing::TestWithParam<Integrator> {};

TEST_P(DampedContact, NeverGainsEnergy) {
  constexpr double g = 9.81, h0 = 0.005, k = 3000.0, z = 0.02;
  Model m;
  m.integrator = GetParam();
  m.set_rate(kRate_hz);
  m.gravity_m_per_s2 = {0, 0, -g};
  const int mass = models::add_point(m, "ball", PointKind::dynamic, {0, 0, h0}, kMass_kg);
  models::add_contact(m, mass, models::add_plane(m, "floor", {}, {0, 0, 1}), k, z);
  State s = make_state(m);
  const double e0 = kMass_kg * g * h0;
  // energy at step n with the centred velocity (x(n+1) - x(n-1)) / 2dt
  auto energy = [&](double before, double now, double after) {
    const double v = (after - before) / (2.0 * kDt_s);
    const double depth = std::max(0.0, -now);
    return 0.5 * kMass_kg * v * v + kMass_kg * g * now + 0.5 * k * depth * depth;
  };
  double before = s.x_prev[mass].z, now = s.x[mass].z;
  bool impacted = false;
  int bounces = 0;
  double max_after = 0.0;
  for (int n = 0; n < 100'000; ++n) {
    const bool was_in = s.in_contact[mass] != 0;
    step(m, s);
    const double after = s.x[mass].z;
    if (impacted) max_after = std::max(max_after, energy(before, now, after));
    bounces += !was_in && s.in_contact[mass] != 0;
    impacted = impacted || s.in_contact[mass] != 0;
    before = now;
    now = after;
  }
  EXPECT_EQ(s.faults, 0u);
  EXPECT_GT(bounces, 3) << "the ball should bounce several times";
  EXPECT_LE(max_after, e0 * (1.0 + 1e-9)) << "energy gained: " << (max_after - e0) / e0;
  // it comes to rest on the floor at the static depth m g / k
  EXPECT_NEAR(s.x[mass].z, -kMass_kg * g / k, 1e-7);
}

INSTANTIATE_TEST_SUITE_P(Integrators, DampedContact,
                         ::testing::Values(Integrator::cordis, Integrator::symplectic_euler, Integrator::implicit_euler),
                         [](const auto& p) { return std::string(to_string(p.param)); });

// the 4 x 4 grid pressed 0.1 mm into a box top, hand still for 5 s at 5 kHz: no limit cycle
TEST(Energy, RestingBodyDoesNotChatter) {
  constexpr double k = 3000.0, press = 0.0001, top = 0.012;
  Model m;
  m.set_rate(kRate_hz);
  models::add_body(m, {0, 0, top - press});
  const int box = models::add_boxes(m, "table", {{{0, 0, top / 2}, {0.02, 0.02, top / 2}}});
  for (int i = 0; i <= 16; ++i) models::add_contact(m, m.proxies[0].point + i, box, k, 0.02);
  haptics::apply(*haptics::preset("CM1"), m);
  State s = make_state(m);
  step(m, s);
  const Vec3 force = s.proxy_force_n[0];
  const std::vector<std::uint8_t> touching = s.in_contact;
  EXPECT_NEAR(force.z, 16 * k * press, 1e-9 * 16 * k * press);
  EXPECT_EQ(std::count(touching.begin(), touching.end(), 1), 17);
  int changed = 0, toggled = 0;
  for (int n = 1; n < 5 * static_cast<int>(kRate_hz); ++n) {
    step(m, s);
    changed += norm(s.proxy_force_n[0] - force) > 1e-9 * norm(force);
    toggled += s.in_contact != touching;
  }
  EXPECT_EQ(changed, 0);
  EXPECT_EQ(toggled, 0);
}

}  // namespace
}  // namespace enact::physics
