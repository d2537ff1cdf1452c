// 16 simultaneous contacts of the grid, each at its own depth: the device force is exactly the
// sum of the forces on the masses feeding it, and the computer models' pins and thresholds
// follow the per-mass contacts.
#include <gtest/gtest.h>

#include <cstdint>

#include "tests/physics/models.h"

namespace enact::physics {
namespace {

constexpr double kK = 3000.0;
constexpr double kZ = 0.02;
constexpr double kBody_z = 0.010;
// grid masses (bit i, row-major) standing over a column whose top is above them
constexpr std::uint32_t kTouching = 0xB6D3;

// mass i of the contact mask is (i + 1) * 0.05 mm deep into its own column
double depth_of(int i) { return (kTouching >> i) & 1u ? (i + 1) * 0.00005 : 0.0; }

// the grid over a union of 16 columns, one under each mass, with tops at different heights
// (the body never rotates: steps give different depths); the centre rests on a plane of its own
Model stepped_columns() {
  Model m;
  m.set_rate(5000.0);
  models::add_body(m, {0, 0, kBody_z});
  const Proxy& p = m.proxies[0];
  std::vector<std::pair<Vec3, Vec3>> columns;
  for (int i = 0; i < 16; ++i) {
    const Vec3 at = m.points[p.first_body + i].offset_m;
    const double top = (kTouching >> i) & 1u ? kBody_z + depth_of(i) : kBody_z - 0.001;
    columns.push_back({{at.x, at.y, top / 2}, {models::kPitch_m / 2, models::kPitch_m / 2, top / 2}});
  }
  const int steps = models::add_boxes(m, "steps", columns);
  for (int i = 0; i < 16; ++i) models::add_contact(m, p.first_body + i, steps, kK, kZ);
  models::add_contact(m, p.point, models::add_plane(m, "rest", {0, 0, kBody_z + 0.0005}, {0, 0, 1}), kK, kZ);
  return m;
}

// the applied computer model's pins after one step, checking the device force on the way
std::uint32_t pins_after_step(Model& m, const std::string& name) {
  const haptics::ComputerModel cm = *haptics::preset(name);
  haptics::apply(cm, m);
  State s = make_state(m);
  step(m, s);
  // the device feels exactly the sum, in point order, of the forces on the points feeding it
  Vec3 sum;
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    if (m.points[i].kind == PointKind::kinematic && m.points[i].feeds_device) sum += s.f[i];
  }
  EXPECT_EQ(s.proxy_force_n[0], sum) << name;
  return haptics::pins(cm, m, s);
}

TEST(Contacts, SixteenDepthsSumExactlyIntoTheDeviceForce) {
  Model m = stepped_columns();
  haptics::apply(*haptics::preset("CM1"), m);
  State s = make_state(m);
  step(m, s);
  const Proxy& p = m.proxies[0];
  double expected = 0.0;
  for (int i = 0; i < 16; ++i) {
    SCOPED_TRACE(i);
    const Vec3 f = s.f[p.first_body + i];
    EXPECT_EQ(s.in_contact[p.first_body + i] != 0, ((kTouching >> i) & 1u) != 0);
    EXPECT_EQ(f.x, 0.0);
    EXPECT_EQ(f.y, 0.0);
    EXPECT_NEAR(f.z, kK * depth_of(i), 1e-12 * kK * 0.001);
    expected += kK * depth_of(i);
  }
  // the centre is pushed by its plane but does not feed the device under CM1
  EXPECT_NEAR(s.f[p.point].z, kK * 0.0005, 1e-12);
  Vec3 grid_sum;
  for (int i = 0; i < 16; ++i) grid_sum += s.f[p.first_body + i];
  EXPECT_EQ(s.proxy_force_n[0], grid_sum);
  EXPECT_NEAR(s.proxy_force_n[0].z, expected, 1e-12 * expected);
}

TEST(Contacts, PinsFollowTheContactMask) {
  Model m = stepped_columns();
  EXPECT_EQ(pins_after_step(m, "CM1"), kTouching);
  EXPECT_EQ(pins_after_step(m, "CM3"), ~kTouching & 0xffffu);
  EXPECT_EQ(pins_after_step(m, "CM0"), 0u);
}

// CM2: 3 mm of penetration before force is felt; the pins rise at first contact
TEST(Contacts, ThresholdModelFeelsOnlyPastThreeMillimetres) {
  constexpr double top = 0.012;
  Model m;
  m.set_rate(5000.0);
  models::add_body(m, {0, 0, top + 0.001});
  const int box = models::add_boxes(m, "table", {{{0, 0, top / 2}, {0.02, 0.02, top / 2}}});
  for (int i = 0; i < 16; ++i) models::add_contact(m, m.proxies[0].first_body + i, box, kK, kZ);
  const haptics::ComputerModel cm2 = *haptics::preset("CM2");
  haptics::apply(cm2, m);
  State s = make_state(m);

  models::place_body(m, s, {0, 0, top - 0.001});
  step(m, s);
  EXPECT_EQ(haptics::pins(cm2, m, s), 0xffffu);
  EXPECT_EQ(s.proxy_force_n[0], Vec3{});

  models::place_body(m, s, {0, 0, top - 0.004});
  step(m, s);
  EXPECT_EQ(haptics::pins(cm2, m, s), 0xffffu);
  const double expected = 16 * kK * (0.004 - 0.003);
  EXPECT_NEAR(s.proxy_force_n[0].z, expected, 1e-9 * expected);
  EXPECT_NEAR(norm(s.proxy_force_n[0]), expected, 1e-9 * expected);
}

}  // namespace
}  // namespace enact::physics
