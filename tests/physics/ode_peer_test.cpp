// The ODE peer of `enact bench physics` computes real contact forces: a body pressed into a box
// at rest feels the spring force in both engines; pressing in, ODE's soft constraint adds the
// damping h k that its ERP and CFM imply; at the bridge's turn, where two of its boxes overlap,
// a point inside both is pushed once.
#include <gtest/gtest.h>

#include <vector>

#include "nodes/enact-bench/bench_physics_ode.h"
#include "tests/physics/models.h"

namespace enact::physics {
namespace {

using cli::ode_peer::Scene;

constexpr double kRate_hz = 5000.0;
constexpr double kStiffness_n_per_m = 6000.0;
constexpr double kDamping_n_s_per_m = 0.02;
constexpr double kPress_m = 1e-4;
constexpr double kTop_m = 0.01;
constexpr int kGrid = 16;
// both engines within this share of the force expected (ODE's body of 10^6 kg moves by about
// 4e-9 of it under the contacts in a step)
constexpr double kRelativeTolerance = 1e-6;

// the device force of both engines at the end of a hand motion
struct Forces {
  Vec3 ours;
  Vec3 ode;
  int ode_contacts = 0;
};

Forces drive(const Model& m, const std::vector<Vec3>& motion) {
  State s = make_state(m);
  Scene ode(m);
  Forces f;
  for (const Vec3& p : motion) {
    s.proxy_position_m[0] = p;
    step(m, s);
    f.ode = ode.step(p);
  }
  f.ours = s.proxy_force_n[0];
  f.ode_contacts = ode.contacts();
  return f;
}

// from 1 mm above `to`, down at `speed` until it; then, when `hold`, one step still there
std::vector<Vec3> press(const Vec3& to, double speed_m_per_s, bool hold) {
  std::vector<Vec3> motion;
  const double step_m = speed_m_per_s / kRate_hz;
  for (double above = 1e-3; above > 0.5 * step_m; above -= step_m) motion.push_back(to + Vec3{0.0, 0.0, above});
  motion.push_back(to);
  if (hold) motion.push_back(to);
  return motion;
}

// the 4 x 4 body over a 40 mm slab whose top is at kTop_m, every grid mass in contact with it
Model body_on_slab() {
  Model m;
  m.name = "slab";
  m.source = "slab.yaml";
  m.set_rate(kRate_hz);
  models::add_body(m, {0.0, 0.0, kTop_m + 1e-3});
  const int slab = models::add_boxes(m, "slab", {{{0.0, 0.0, kTop_m / 2}, {0.02, 0.02, kTop_m / 2}}});
  for (int i = 0; i < kGrid; ++i) models::add_contact(m, m.proxies[0].first_body + i, slab, kStiffness_n_per_m, kDamping_n_s_per_m);
  haptics::apply(*haptics::preset("CM1"), m);
  return m;
}

void expect_force(const Vec3& f, double z_n) {
  EXPECT_NEAR(f.x, 0.0, 1e-9);
  EXPECT_NEAR(f.y, 0.0, 1e-9);
  EXPECT_NEAR(f.z, z_n, kRelativeTolerance * z_n);
}

TEST(OdePeer, PressedAtRestBothEnginesGiveTheSpringForce) {
  const Forces f = drive(body_on_slab(), press({0.0, 0.0, kTop_m - kPress_m}, 0.01, true));
  const double spring_n = kGrid * kStiffness_n_per_m * kPress_m;  // 9.6 N
  expect_force(f.ours, spring_n);
  expect_force(f.ode, spring_n);
  EXPECT_EQ(f.ode_contacts, kGrid);
}

TEST(OdePeer, PressingInOdeAddsTheDampingItsErpAndCfmImply) {
  // ODE solves J v = ERP depth / h - CFM lambda for the body that does not move within the
  // step: lambda = k depth - (c + h k) (J v), J v the separating speed (here -speed)
  const double speed = 0.01;
  const Forces f = drive(body_on_slab(), press({0.0, 0.0, kTop_m - kPress_m}, speed, false));
  const double h = 1.0 / kRate_hz;
  expect_force(f.ours, kGrid * (kStiffness_n_per_m * kPress_m + kDamping_n_s_per_m * speed));
  expect_force(f.ode, kGrid * (kStiffness_n_per_m * kPress_m + (kDamping_n_s_per_m + h * kStiffness_n_per_m) * speed));
}

TEST(OdePeer, AtTheBridgesTurnAPointInsideTwoBoxesIsPushedOnce) {
  // inside the first turn, where the whole grid fits on the top (the bench's turn position):
  // some grid masses lie in both segments' boxes
  const Model m = models::bridge(kRate_hz);
  const auto& line = m.objects[m.find_object("bridge")].path.centerline_m;
  const Vec3 first = models::unit(line[1] - line[0]);
  const Vec3 second = models::unit(line[2] - line[1]);
  Vec3 centre = line[1] + second * 1.5e-3 - first * 2.5e-3;
  centre.z = m.objects[m.find_object("bridge")].path.top_z_m - kPress_m;
  const Forces f = drive(m, press(centre, 0.01, true));
  const double spring_n = kGrid * kStiffness_n_per_m * kPress_m;
  expect_force(f.ours, spring_n);
  expect_force(f.ode, spring_n);
  EXPECT_EQ(f.ode_contacts, kGrid);
}

}  // namespace
}  // namespace enact::physics
