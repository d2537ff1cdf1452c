// The step allocates nothing: on the bridge with the body (rigid and deformable) entering and
// leaving contact and crossing the corner of a turn (with friction and without), and on a
// model with every link type under every integrator.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/physics/models.h"
#include "tests/support/alloc_guard.h"

namespace enact::physics {
namespace {

constexpr int kSteps = 10'000;

TEST(NoAllocation, TheGuardCountsAllocations) {
  std::vector<int> v;
  std::size_t counted = 0;
  {
    enact::test::AllocGuard guard;
    v.push_back(1);
    counted = guard.allocations();
  }
  asm volatile("" : : "g"(v.data()) : "memory");
  EXPECT_GT(counted, 0u);
}

// the body traces a rose around the first turn's corner (through the corner ten times) while
// bobbing from above the top to 2 mm into it; with friction, its pairs stick and slide
void bridge_rose(const Model& m) {
  const Vec3 corner = m.objects[m.find_object("bridge")].path.centerline_m[1];
  const Proxy& p = m.proxies[0];
  State s = make_state(m);
  int entered = 0, left = 0, near_corner_in_contact = 0, sliding = 0;
  std::size_t allocations = 0;
  {
    enact::test::AllocGuard guard;
    for (int n = 0; n < kSteps; ++n) {
      const double a = 2.0 * models::kPi * n / kSteps;
      const double r = 0.012 * std::cos(5.0 * a);
      s.proxy_position_m[0] = {corner.x + r * std::cos(a), corner.y + r * std::sin(a), 0.0115 + 0.0015 * std::sin(3.0 * a)};
      const std::uint8_t was = s.in_contact[p.first_body];
      step(m, s);
      entered += !was && s.in_contact[p.first_body];
      left += was && !s.in_contact[p.first_body];
      near_corner_in_contact += std::abs(r) < 0.001 && norm(s.proxy_force_n[0]) > 0.0;
      for (const ContactState& c : s.contacts) sliding += c.sliding;
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(entered, 0);
  EXPECT_GT(left, 0);
  EXPECT_GT(near_corner_in_contact, 0);
  EXPECT_EQ(sliding > 0, m.contacts.front().friction.enabled());
  EXPECT_EQ(s.faults, 0u);
}

TEST(NoAllocation, BridgeStepWithTheBodyCrossingContactsAndACorner) { bridge_rose(models::bridge(5000.0, "CM1")); }

TEST(NoAllocation, FrictionalBridgeStep) {
  Model m = models::bridge(5000.0, "CM1");
  models::add_friction(m, {0.6, 0.4, 2000.0});
  bridge_rose(m);
}

// the deformable fingertip: its masses and their links stepped with the contacts
TEST(NoAllocation, DeformableBridgeStep) {
  bridge_rose(models::bridge(5000.0, "CM1", enact::test::source_path("launch/scenes/bridge_deformable.yaml")));
}

TEST(NoAllocation, FrictionalDeformableBridgeStep) {
  Model m = models::bridge(5000.0, "CM1", enact::test::source_path("launch/scenes/bridge_deformable.yaml"));
  models::add_friction(m, {0.6, 0.4, 2000.0});
  bridge_rose(m);
}

// masses chained by every link type, driven by a moving proxy, against a box and a plane
Model every_link_type() {
  Model m;
  m.set_rate(5000.0);
  m.gravity_m_per_s2 = {0, 0, -9.81};
  const int anchor = models::add_point(m, "anchor", PointKind::fixed, {0, 0, 0.02});
  const int hand = models::add_point(m, "hand", PointKind::kinematic, {0.01, 0, 0.02});
  m.points[hand].proxy = 0;
  m.proxies.push_back({"hand", hand, -1, 0, 0, 0.0, 0});
  const char* names[4] = {"m0", "m1", "m2", "m3"};
  int mass[4];
  for (int i = 0; i < 4; ++i) mass[i] = models::add_point(m, names[i], PointKind::dynamic, {0.003 * i, 0, 0.015}, 0.01);
  models::add_link(m, "spring", LinkType::spring, anchor, mass[0], 200.0, 0.0);
  m.links.back().rest_length_m = 0.004;
  models::add_link(m, "damper", LinkType::damper, mass[0], mass[1], 0.0, 0.05);
  m.links.back().rest_length_m = 0.003;
  models::add_link(m, "spring_damper", LinkType::spring_damper, mass[1], mass[2], 300.0, 0.02);
  models::add_link(m, "contact", LinkType::contact, mass[2], mass[3], 500.0, 0.02);
  m.links.back().threshold_m = 0.004;
  models::add_link(m, "nonlinear", LinkType::nonlinear_spring, mass[3], anchor, 100.0, 0.0);
  Link& nl = m.links.back();
  nl.rest_length_m = 0.005;
  nl.cubic_n_per_m3 = 1e7;
  nl.max_stiffness_n_per_m = 1000.0;
  nl.clip_elongation_m = std::sqrt((nl.max_stiffness_n_per_m - nl.stiffness_n_per_m) / (3.0 * nl.cubic_n_per_m3));
  models::add_link(m, "nonlinear_isotropic", LinkType::nonlinear_spring, hand, mass[1], 100.0, 0.0);
  m.links.back().cubic_n_per_m3 = 1e7;
  m.links.back().max_stiffness_n_per_m = 1000.0;
  m.links.back().clip_elongation_m = nl.clip_elongation_m;
  models::add_link(m, "hand_spring", LinkType::spring_damper, hand, mass[0], 200.0, 0.01);
  const int box = models::add_boxes(m, "box", {{{0.005, 0, 0.005}, {0.01, 0.01, 0.005}}});
  const int floor = models::add_plane(m, "floor", {0, 0, 0}, {0, 0, 1});
  for (int i = 0; i < 4; ++i) {
    models::add_contact(m, mass[i], box, 1000.0, 0.02);
    models::add_contact(m, mass[i], floor, 1000.0, 0.02);
  }
  return m;
}

// driven for kSteps by the hand, with friction on every contact pair of the masses or without
void drive(Integrator integrator, bool friction) {
  SCOPED_TRACE(std::string(to_string(integrator)) + (friction ? " with friction" : ""));
  Model m = every_link_type();
  m.integrator = integrator;
  if (friction) models::add_friction(m, {0.6, 0.4, 500.0});
  State s = make_state(m);
  int contacts = 0;
  std::size_t allocations = 0;
  {
    enact::test::AllocGuard guard;
    for (int n = 0; n < kSteps; ++n) {
      s.proxy_position_m[0] = {0.01 + 0.01 * std::sin(2.0 * models::kPi * n / 2000.0), 0, 0.02};
      step(m, s);
      for (const std::uint8_t c : s.in_contact) contacts += c;
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(contacts, 0);
  EXPECT_EQ(s.faults, 0u);
}

TEST(NoAllocation, EveryLinkTypeUnderEveryIntegrator) {
  for (const Integrator integrator : {Integrator::cordis, Integrator::symplectic_euler, Integrator::implicit_euler}) {
    drive(integrator, false);
    drive(integrator, true);
  }
}

}  // namespace
}  // namespace enact::physics
