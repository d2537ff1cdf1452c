// Hard cases, each checked for energy (no gain beyond the stated bound), tunnelling, NaN and
// the divergence guard: a stiff chain near its stability bound (and past the bound the
// per-mass sum used to miss), a mass ratio of 10^6, grazing along an edge and into a corner of
// a union, impacts at 1.8 m/s at 1 kHz, the bridge at 44 kHz with 30 000 N/m, and a body
// resting on a face while sliding across a seam.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/physics/stability.h"
#include "tests/physics/models.h"

namespace enact::physics {
namespace {

constexpr double kG = 9.81;

// a spring_damper along x with a rest length between two points
void add_spring(Model& m, int a, int b, double k, double rest_m) {
  const int l = models::add_link(m, "s" + std::to_string(b), LinkType::spring, a, b, k, 0.0);
  m.links[l].rest_length_m = rest_m;
}

// masses in a line along x from a fixed anchor, springs of rest length 1 mm, the last
// `pulled` masses stretched by `stretch_m` each; masses[i] is the mass of point i + 1
Model line(Integrator integrator, double rate_hz, const std::vector<double>& masses, const std::vector<double>& k, double stretch_m) {
  Model m;
  m.integrator = integrator;
  m.set_rate(rate_hz);
  models::add_point(m, "anchor", PointKind::fixed, {});
  for (std::size_t i = 0; i < masses.size(); ++i) {
    const double x = 0.001 * static_cast<double>(i + 1) + stretch_m * static_cast<double>(i + 1);
    models::add_point(m, "m" + std::to_string(i + 1), PointKind::dynamic, {x, 0, 0}, masses[i]);
    add_spring(m, static_cast<int>(i), static_cast<int>(i + 1), k[i], 0.001);
  }
  return m;
}

// the quantity the explicit schemes keep exactly for linear springs in 1D:
// sum m v(n+1/2)^2 / 2 + sum k e(n) e(n+1) / 2, v(n+1/2) = (x(n+1) - x(n)) / dt
double shadow_energy_j(const Model& m, const std::vector<double>& before, const std::vector<double>& after) {
  double e = 0.0;
  for (std::size_t i = 1; i < m.points.size(); ++i) {
    const double v = (after[i] - before[i]) / m.dt_s;
    e += 0.5 * m.points[i].mass_kg * v * v;
  }
  for (const Link& l : m.links) {
    e += 0.5 * l.stiffness_n_per_m * (before[l.b] - before[l.a] - l.rest_length_m) * (after[l.b] - after[l.a] - l.rest_length_m);
  }
  return e;
}

std::vector<double> xs(const State& s) {
  std::vector<double> out;
  for (const Vec3& x : s.x) out.push_back(x.x);
  return out;
}

struct Conservation {
  double drift = 0.0;  // largest |I - I0| / I0
  double largest_x_m = 0.0;
};

Conservation conserve(const Model& m, int steps) {
  State s = make_state(m);
  std::vector<double> before = xs(s);
  step(m, s);
  std::vector<double> after = xs(s);
  const double i0 = shadow_energy_j(m, before, after);
  Conservation c;
  for (int n = 1; n < steps; ++n) {
    before = after;
    step(m, s);
    after = xs(s);
    c.drift = std::max(c.drift, std::abs(shadow_energy_j(m, before, after) - i0) / i0);
    for (const double x : after) c.largest_x_m = std::max(c.largest_x_m, std::abs(x));
  }
  EXPECT_EQ(s.faults, 0u);
  EXPECT_TRUE(models::state_finite(s));
  return c;
}

// 20 masses of 10 g at 1 kHz: the alternating mode of a chain loads each spring from both ends,
// so the bound is 4k < 4M (k < M = m / dt^2 = 10 000 N/m)
constexpr int kChain = 20;
constexpr double kChainMass_kg = 0.01;
constexpr double kChainM = kChainMass_kg * 1e6;

Model chain(Integrator integrator, double k) {
  return line(integrator, 1000.0, std::vector<double>(kChain, kChainMass_kg), std::vector<double>(kChain, k), 1e-5);
}

class StiffChain : public ::testing::TestWithParam<Integrator> {};

TEST_P(StiffChain, NearItsBoundKeepsItsEnergy) {
  const Model m = chain(GetParam(), 0.97 * kChainM);
  EXPECT_TRUE(analyze_stability(m).stable());
  const Conservation c = conserve(m, 200'000);
  EXPECT_LT(c.drift, 1e-9);
  EXPECT_LT(c.largest_x_m, 0.05) << "a 21 mm chain stays within 50 mm of its anchor";
}

// at 1.5 M each mass's plain sum of stiffness (2k = 3M) is below 4M, yet the chain diverges:
// the analysis now refuses it, and run anyway the guard trips, resets and stays finite
TEST_P(StiffChain, PastItsBoundIsRefusedAndTripsTheGuard) {
  const Model m = chain(GetParam(), 1.5 * kChainM);
  const StabilityReport r = analyze_stability(m);
  EXPECT_FALSE(r.stable());
  EXPECT_NE(instability_message(m, r).find("fix:"), std::string::npos);
  State s = make_state(m);
  for (int n = 0; n < 20'000 && s.faults == 0; ++n) step(m, s);
  EXPECT_GT(s.faults, 0u);
  EXPECT_TRUE(s.last_fault == Fault::runaway_position || s.last_fault == Fault::runaway_speed || s.last_fault == Fault::nonfinite_state);
  EXPECT_TRUE(models::state_finite(s));
  EXPECT_EQ(s.x[kChain].x, m.points[kChain].position_m.x) << "the guard put the chain back at its start";
}

INSTANTIATE_TEST_SUITE_P(Explicit, StiffChain, ::testing::Values(Integrator::cordis, Integrator::symplectic_euler),
                         [](const auto& p) { return std::string(to_string(p.param)); });

// 1 kg and 1 mg (ratio 10^6) at 1 kHz: the light mass's spring at 95 % of its bound
TEST(HardCases, MassRatioOfAMillion) {
  const double light_kg = 1e-6, bound = 2.0 * light_kg * 1e6;  // 2k < 4 m / dt^2
  const Model m = line(Integrator::cordis, 1000.0, {1.0, light_kg}, {1000.0, 0.95 * bound}, 1e-4);
  EXPECT_TRUE(analyze_stability(m).stable());
  const Conservation c = conserve(m, 1'000'000);
  EXPECT_LT(c.drift, 1e-8);
  EXPECT_LT(c.largest_x_m, 0.01);
}

// a 10 g mass under gravity dropped onto a union (contact k, z = 0.05 N s/m) from `x0` with
// `v0`: the largest energy gain in flight, m v^2/2 + m g (z(n) + z(n-1))/2 (what the explicit
// schemes keep exactly in flight) against that after the first step, and the deepest contact
struct Slide {
  double gain = 0.0;
  double deepest_m = 0.0;
  Vec3 end_m;
};

Slide slide(Model m, Vec3 x0, Vec3 v0, int steps, double k) {
  const int ball = models::add_point(m, "ball", PointKind::dynamic, x0, 0.01);
  m.points[ball].velocity_m_per_s = v0;
  m.gravity_m_per_s2 = {0, 0, -kG};
  models::add_contact(m, ball, 0, k, 0.05);
  m.contacts.back().edge_skin_m = 0.001;
  m.index_boxes();
  State s = make_state(m);
  auto energy = [&] { return models::flight_energy_j(s, ball, 0.01, kG); };
  step(m, s);
  const double e0 = energy();
  Slide r;
  for (int n = 1; n < steps; ++n) {
    step(m, s);
    if (!s.in_contact[ball] && !s.contacts[0].active) r.gain = std::max(r.gain, (energy() - e0) / std::abs(e0));
    if (s.contacts[0].active) r.deepest_m = std::max(r.deepest_m, s.contacts[0].depth_m);
    EXPECT_TRUE(models::state_finite(s));
  }
  EXPECT_EQ(s.faults, 0u);
  r.end_m = s.x[ball];
  return r;
}

// a slab (top at z = 0, 40 x 40 mm) with a wall standing on it at x > 10 mm: a concave corner
Model slab_and_wall(double rate_hz) {
  Model m;
  m.set_rate(rate_hz);
  models::add_boxes(m, "L", {{{0, 0, -0.005}, {0.02, 0.02, 0.005}}, {{0.015, 0, 0.01}, {0.005, 0.02, 0.01}}});
  return m;
}

// sliding at 0.5 m/s into the corner, from 0.2 mm above the slab (hitting the wall's face just
// above its foot, then dropping into the slab at the foot) and from resting on the slab's top
// (sliding under the wall's foot): held by the wall's face, never deeper than 1 mm, back on the
// near side of the wall on or in the slab's top after 60 ms, no energy gain beyond 0.1 %.
// Both tunnelled: the wall's bottom, flush on the slab, counted as exposed and pushed the point
// down through the slab; under the wall's foot, in the slab only, its top covered there, the
// slab's far end pushed the point on under the wall (now the wall's face, extended below its
// foot, pushes it back)
TEST(HardCases, GrazingIntoACornerOfAUnion) {
  const double k = 3000.0;
  for (const double z0_m : {0.0002, 0.0}) {
    const Slide r = slide(slab_and_wall(5000.0), {0, 0, z0_m}, {0.5, 0, 0}, 300, k);
    EXPECT_LT(r.gain, 1e-3) << "from z " << z0_m;
    EXPECT_LT(r.deepest_m, 0.001) << "from z " << z0_m;
    EXPECT_LT(r.end_m.x, 0.01) << "through the wall from z " << z0_m;
    EXPECT_GT(r.end_m.z, -0.001) << "through the top from z " << z0_m;
  }
}

// landing grazing 0.1 mm inside the side edge, sliding along it and drifting off: it rides
// over the edge (never pushed back in by the side face), falls, no energy gain beyond 0.1 %
TEST(HardCases, GrazingAlongAnEdge) {
  const double k = 3000.0;
  const Slide r = slide(slab_and_wall(5000.0), {-0.015, 0.0199, 0.0002}, {0.1, 0.01, 0}, 1000, k);
  EXPECT_LT(r.gain, 1e-3);
  EXPECT_LT(r.deepest_m, 0.001);
  EXPECT_GT(r.end_m.y, 0.02) << "it left over the edge";
  EXPECT_LT(r.end_m.z, -0.01) << "and fell";
}

// dropped onto a 10 mm slab at 1.8 m/s (1.8 mm per step at 1 kHz): never through the slab;
// the passive contact gains no energy (10^-9), the plain damped one none beyond 0.1 %
TEST(HardCases, ImpactAt1p8MetresPerSecondAt1kHz) {
  for (const bool passive : {false, true}) {
    Model m;
    m.set_rate(1000.0);
    m.gravity_m_per_s2 = {0, 0, -kG};
    models::add_boxes(m, "slab", {{{0, 0, -0.005}, {0.02, 0.02, 0.005}}});
    const int ball = models::add_point(m, "ball", PointKind::dynamic, {0, 0, 0.0005}, 0.01);
    m.points[ball].velocity_m_per_s = {0, 0, -1.8};
    models::add_contact(m, ball, 0, 20000.0, passive ? 0.0 : 0.05);
    m.contacts[0].passive = passive;
    m.index_boxes();
    EXPECT_TRUE(analyze_stability(m).stable());
    State s = make_state(m);
    const double e0 = 0.5 * 0.01 * 1.8 * 1.8 + 0.01 * kG * 0.0005;
    double lowest = 0.0, gain = 0.0;
    for (int n = 0; n < 5000; ++n) {
      step(m, s);
      lowest = std::min(lowest, s.x[ball].z);
      if (s.x[ball].z > 0.0 && s.x_prev[ball].z > 0.0) {
        gain = std::max(gain, (models::flight_energy_j(s, ball, 0.01, kG) - e0) / e0);
      }
    }
    EXPECT_EQ(s.faults, 0u);
    EXPECT_TRUE(models::state_finite(s));
    EXPECT_GT(lowest, -0.01) << "through the slab (passive " << passive << ")";
    EXPECT_GT(s.x[ball].z, -0.0001) << "ends on or above the top";
    EXPECT_LT(gain, passive ? 1e-9 : 1e-3) << "passive " << passive;
  }
}

// the bridge at 44 kHz with 30 000 N/m on every contact, the body wobbling at a turn (all 16
// grid masses on the top): the device force never exceeds what the contact law allows, the
// contacts never return more work to the device over the 1 s cycle than 10^-6 J
TEST(HardCases, Bridge44kHzAt30000NPerMetre) {
  Model m = models::bridge(44000.0);
  for (ContactPair& c : m.contacts) c.stiffness_n_per_m = 30000.0;
  const models::Segment a = models::bridge_segment(m, 0), b = models::bridge_segment(m, 1);
  const auto& line = m.objects[m.find_object("bridge")].path.centerline_m;
  Vec3 centre = line[1] + b.along * 0.0015 - a.along * 0.0025;
  centre.z -= 0.0001;
  State s = make_state(m);
  models::place_body(m, s, centre);
  double work = 0.0, worst_excess = 0.0;
  Vec3 before = centre;
  for (int n = 1; n <= 44000; ++n) {
    const double phase = 2.0 * models::kPi * n / 44000.0;
    const Vec3 now = centre + a.along * (0.0012 * std::sin(2.0 * phase)) + b.along * (0.0012 * std::sin(3.0 * phase));
    s.proxy_position_m[0] = now;
    step(m, s);
    double allowed = 0.0;
    for (std::size_t k = 0; k < s.contacts.size(); ++k) {
      const ContactPair& c = m.contacts[k];
      if (s.contacts[k].active && m.points[c.point].feeds_device) allowed += c.stiffness_n_per_m * s.contacts[k].depth_m + c.damping_n_s_per_m * norm(s.v[c.point]);
    }
    worst_excess = std::max(worst_excess, norm(s.proxy_force_n[0]) - allowed * (1.0 + 1e-12));
    work += dot(s.proxy_force_n[0], now - before);
    before = now;
  }
  EXPECT_EQ(s.faults, 0u);
  EXPECT_TRUE(models::state_finite(s));
  EXPECT_LE(worst_excess, 0.0);
  EXPECT_LT(work, 1e-6) << "energy returned to the device over a closed cycle (J)";
}

// the 4 x 4 grid pressed 0.1 mm into two boxes whose tops meet at a seam, sliding across it at
// 0.05 m/s (5 kHz): the same 16 contacts and the same upward force on every step, nothing sideways
TEST(HardCases, RestingOnAFaceSlidingAcrossASeam) {
  constexpr double k = 3000.0, press = 0.0001, top = 0.012;
  Model m;
  m.set_rate(5000.0);
  models::add_body(m, {-0.01, 0, top - press});
  const int table = models::add_boxes(m, "table", {{{-0.015, 0, top / 2}, {0.015, 0.02, top / 2}}, {{0.015, 0, top / 2}, {0.015, 0.02, top / 2}}});
  for (int i = 1; i <= 16; ++i) models::add_contact(m, m.proxies[0].point + i, table, k, 0.0);
  m.index_boxes();
  haptics::apply(*haptics::preset("CM1"), m);
  State s = make_state(m);
  const double expected = 16 * k * press;
  int steps_off = 0;
  double worst_z = 0.0, worst_side = 0.0;
  for (int n = 1; n <= 2000; ++n) {
    s.proxy_position_m[0] = {-0.01 + 0.05 * n / 5000.0, 0, top - press};
    step(m, s);
    int touching = 0;
    for (int i = 1; i <= 16; ++i) touching += s.in_contact[m.proxies[0].point + i];
    steps_off += touching != 16;
    worst_z = std::max(worst_z, std::abs(s.proxy_force_n[0].z - expected));
    worst_side = std::max(worst_side, std::hypot(s.proxy_force_n[0].x, s.proxy_force_n[0].y));
  }
  EXPECT_EQ(s.faults, 0u);
  EXPECT_TRUE(models::state_finite(s));
  EXPECT_EQ(steps_off, 0);
  EXPECT_LT(worst_z, 1e-9 * expected);
  EXPECT_LT(worst_side, 1e-12);
}

}  // namespace
}  // namespace enact::physics
