// The passive (energy-consistent) contact: a mass bouncing on an undamped plane keeps its
// energy where the plain contact gains it; the ledger never goes negative; a device moving
// through a passive contact never gets back more work than it put in; the scene key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/physics/models.h"

namespace enact::physics {
namespace {

// the bouncing mass of the references (core/physics/reference.h): 0.01 kg dropped from 5 mm
// onto a 2000 N/m plane under 9.81 m/s^2
constexpr double kMass_kg = 0.01;
constexpr double kGravity_m_per_s2 = 9.81;
constexpr double kStiffness_n_per_m = 2000.0;
using reference::bounce;

double flight_energy_j(const State& s) { return models::flight_energy_j(s, 0, kMass_kg, kGravity_m_per_s2); }

struct Bounce {
  double drift = 0.0;      // (E - E0) / E0, largest in magnitude over the steps in flight
  double min_ledger_j = 0.0;
  int impacts = 0;
};

Bounce run(const Model& m, long steps) {
  State s = make_state(m);
  step(m, s);
  const double e0 = flight_energy_j(s);
  Bounce b;
  for (long n = 1; n < steps; ++n) {
    const bool was_in = s.in_contact[0] != 0;
    step(m, s);
    b.impacts += !was_in && s.in_contact[0];
    b.min_ledger_j = std::min(b.min_ledger_j, s.contacts[0].ledger_j);
    if (s.x[0].z <= 0.0 || s.x_prev[0].z <= 0.0) continue;
    const double drift = (flight_energy_j(s) - e0) / e0;
    if (std::abs(drift) > std::abs(b.drift)) b.drift = drift;
  }
  EXPECT_EQ(s.faults, 0u);
  return b;
}

struct Case {
  Integrator integrator;
  double rate_hz;
};

class PassiveBounce : public ::testing::TestWithParam<Case> {};

// 10^6 steps (1000 s at 1 kHz, thousands of impacts): within 10^-6 of the first energy
TEST_P(PassiveBounce, KeepsItsEnergy) {
  const Bounce b = run(bounce(GetParam().integrator, GetParam().rate_hz, true), 1'000'000);
  EXPECT_GT(b.impacts, 1000);
  EXPECT_LT(std::abs(b.drift), 1e-6);
  EXPECT_GE(b.min_ledger_j, -1e-15) << "the contact returned more than it absorbed";
}

INSTANTIATE_TEST_SUITE_P(Rates, PassiveBounce,
                         ::testing::Values(Case{Integrator::cordis, 1000.0}, Case{Integrator::cordis, 5000.0},
                                           Case{Integrator::symplectic_euler, 1000.0}, Case{Integrator::symplectic_euler, 5000.0}),
                         [](const auto& p) { return std::string(to_string(p.param.integrator)) + "_" + std::to_string(static_cast<int>(p.param.rate_hz)); });

// the same measure on the plain contact: the sampled spring gains energy at 1 kHz (cordis x13)
TEST(Passive, PlainContactGainsWhereThePassiveOneDoesNot) {
  const Bounce plain = run(bounce(Integrator::cordis, 1000.0, false), 1'000'000);
  EXPECT_GT(plain.drift, 1.0);
}

// with damping the passive contact only loses energy, like the plain one
TEST(Passive, DampedNeverGains) {
  for (const Integrator integrator : {Integrator::cordis, Integrator::symplectic_euler, Integrator::implicit_euler}) {
    const Bounce b = run(bounce(integrator, 1000.0, true, 0.02), 100'000);
    EXPECT_LE(b.drift, 1e-12) << to_string(integrator);
    EXPECT_GT(b.impacts, 3) << to_string(integrator);
  }
}

// a device point driven into a plane at one speed and back out at another, the surface
// crossed at many phases between two samples: the work the contact does on the device over
// the whole cycle, sum of F(n) . (x(n+1) - x(n-1)) / 2, is never positive with the passive
// contact (the plain one gives some back at some phases)
double device_work_j(bool passive, double phase) {
  constexpr double rate_hz = 1000.0, in_m = 0.00005, out_m = 0.00008, depth_m = 0.002, start_m = 0.001;
  Model m;
  m.set_rate(rate_hz);
  const int hand = models::add_point(m, "hand", PointKind::kinematic, {0, 0, start_m});
  m.points[hand].proxy = 0;
  m.proxies.push_back({"hand", hand, -1, 0, 0, 0.0, 0});
  models::add_contact(m, hand, models::add_plane(m, "floor", {}, {0, 0, 1}), kStiffness_n_per_m, 0.0);
  m.contacts[0].passive = passive;
  State s = make_state(m);
  std::vector<Vec3> path{{0, 0, start_m + phase * in_m}};
  while (path.back().z > -depth_m) path.push_back(path.back() - Vec3{0, 0, in_m});
  while (path.back().z < start_m) path.push_back(path.back() + Vec3{0, 0, out_m});
  return models::device_work_j(m, s, path);
}

TEST(Passive, DeviceNeverGetsBackMoreThanItPutIn) {
  double plain_most = -1.0;
  for (int k = 0; k < 100; ++k) {
    const double phase = k / 100.0;
    EXPECT_LE(device_work_j(true, phase), 1e-15) << "phase " << phase;
    plain_most = std::max(plain_most, device_work_j(false, phase));
  }
  EXPECT_GT(plain_most, 1e-9) << "the plain contact returns more at some phase";
}

// a device pressed 1 mm in, wobbling for 1 s at 1 kHz (the ledger gathers the sampled
// spring's errors), then withdrawn: on every step the passive contact pushes no harder than
// the plain one, or than the spring one step's travel deep
TEST(Passive, NeverKicksTheDevice) {
  constexpr double rate_hz = 1000.0;
  std::vector<double> z;
  for (int n = 0; n < 1000; ++n) z.push_back(-0.001 + 0.0005 * std::sin(2.0 * models::kPi * 7.3 * n / rate_hz));
  while (z.back() < 0.001) z.push_back(z.back() + 0.00003);
  Model m;
  m.set_rate(rate_hz);
  const int hand = models::add_point(m, "hand", PointKind::kinematic, {0, 0, z.front()});
  m.points[hand].proxy = 0;
  m.proxies.push_back({"hand", hand, -1, 0, 0, 0.0, 0});
  models::add_contact(m, hand, models::add_plane(m, "floor", {}, {0, 0, 1}), kStiffness_n_per_m, 0.0);
  Model passive = m;
  passive.contacts[0].passive = true;
  State plain_state = make_state(m), passive_state = make_state(passive);
  int controlled = 0;
  for (std::size_t n = 1; n < z.size(); ++n) {
    plain_state.proxy_position_m[0] = passive_state.proxy_position_m[0] = {0, 0, z[n]};
    step(m, plain_state);
    step(passive, passive_state);
    const double plain = plain_state.proxy_force_n[0].z, controlled_force = passive_state.proxy_force_n[0].z;
    const double travel = std::abs(z[n] - z[n - 1]) * 2.0;
    EXPECT_LE(controlled_force, std::max(plain, kStiffness_n_per_m * travel) + 1e-12) << "step " << n;
    controlled += controlled_force != plain;
  }
  EXPECT_GT(controlled, 0) << "the controller acted";
}

TEST(Passive, SceneKey) {
  enact::test::TempDir dir;
  const std::string path = dir.file("s.yaml");
  enact::test::write_file(path, R"(masses: [{name: ball, mass_kg: 0.01, position_m: [0, 0, 0.005]}]
objects: [{name: floor, type: plane, normal: [0, 0, 1]}]
contacts:
  - {masses: [ball], objects: [floor], stiffness_n_per_m: 2000, passive: true}
  - {masses: [ball], objects: [floor], stiffness_n_per_m: 2000}
)");
  const Model m = load_scene(path);
  ASSERT_EQ(m.contacts.size(), 2u);
  EXPECT_TRUE(m.contacts[0].passive);
  EXPECT_FALSE(m.contacts[1].passive);
  EXPECT_EQ(make_state(m).passive, std::vector<int>{0});
}

}  // namespace
}  // namespace enact::physics
