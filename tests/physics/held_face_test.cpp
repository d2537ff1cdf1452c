// The held face (ContactState::hold_at_m, contact.cpp): while a point stays within its hold
// distance the contact skips the full face test. It must change nothing: on random walks
// over the bridge, a rotated union with coplanar tops and a floor of more than 64 tiles
// (the objects the near-box cache does not cover), every step's contacts (active, box, face,
// normal, depth) and device force are bit-identical to those of the full test every step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "tests/physics/models.h"

namespace enact::physics {
namespace {

using models::same_bits;

struct Coverage {
  long contact_steps = 0;  // active contacts with boxes over all steps
  long held = 0;           // of those, with a hold planned
  long tied = 0;           // of those, with a coplanar tie watched
};

// the walk through two states of `m`, with and without the held face; the first difference
// fails the test
Coverage compare(const Model& m, models::Walk walk, long steps) {
  State fast = make_state(m);
  State full = make_state(m);
  full.hold = false;
  Coverage c;
  for (long n = 0; n < steps; ++n) {
    fast.proxy_position_m[0] = full.proxy_position_m[0] = walk.next(m.dt_s);
    step(m, fast);
    step(m, full);
    for (std::size_t k = 0; k < m.contacts.size(); ++k) {
      const ContactState& a = fast.contacts[k];
      const ContactState& b = full.contacts[k];
      const bool same = a.active == b.active && a.box == b.box && a.face == b.face && same_bits(a.normal, b.normal) && same_bits(a.depth_m, b.depth_m);
      if (!same) {
        ADD_FAILURE() << "step " << n << ", contact " << k << " (point " << m.contacts[k].point << "): held active " << a.active << " box " << a.box
                      << " face " << a.face << " depth " << a.depth_m << "; full test active " << b.active << " box " << b.box << " face "
                      << b.face << " depth " << b.depth_m;
        return c;
      }
      if (!a.active || m.objects[m.contacts[k].object].type != ObjectType::boxes) continue;
      ++c.contact_steps;
      c.held += a.hold_r2 > 0.0;
      c.tied += a.hold_r2 > 0.0 && a.ties[0].box >= 0;
    }
    if (!same_bits(fast.proxy_force_n[0], full.proxy_force_n[0])) {
      ADD_FAILURE() << "step " << n << ": device forces differ";
      return c;
    }
  }
  EXPECT_EQ(fast.faults, 0u);
  const double all = static_cast<double>(c.contact_steps);
  std::printf("%ld contact steps with boxes, %.1f %% held, %.1f %% with a tie\n", c.contact_steps, 100.0 * static_cast<double>(c.held) / all,
              100.0 * static_cast<double>(c.tied) / all);
  return c;
}

// a body of 4 x 4 masses and its centre against `object`, 6000 N/m as in the bridge scene
void touch_all(Model& m, int object, double skin_m = 0.001) {
  for (int i = 0; i < static_cast<int>(m.points.size()); ++i) {
    if (m.points[i].kind == PointKind::kinematic) models::add_contact(m, i, object, 6000.0, 0.02);
  }
  for (ContactPair& c : m.contacts) c.edge_skin_m = skin_m;
}

TEST(HeldFace, TheBridgeUnderRandomWalksMatchesTheFullTest) {
  for (double rate_hz : {5000.0, 44000.0}) {
    const Model m = models::bridge(rate_hz);
    const auto& line = m.objects[m.find_object("bridge")].path.centerline_m;
    // the whole bridge from 4 mm into it to 2 mm above it, off its sides onto the floor too
    const Vec3 low{line[0].x - 0.012, line[0].y, 0.008}, high{line[3].x + 0.012, line[3].y, 0.014};
    const Coverage c = compare(m, models::Walk(low, high, 7), 400000);
    // the walk exercised the hold, and the coplanar tops at the turns
    EXPECT_GT(c.held, c.contact_steps / 4) << rate_hz << " Hz";
    EXPECT_GT(c.tied, c.contact_steps / 20) << rate_hz << " Hz";
  }
}

TEST(HeldFace, ATiltedUnionWithCoplanarTopsMatchesTheFullTest) {
  Model m;
  m.set_rate(10000.0);
  models::add_body(m, {0.0, 0.0, 0.02});
  // six overlapping slabs of different thickness and yaw, their tops on one plane tilted by
  // about 10 degrees (through (0, 0, 10 mm)), and two blocks sticking out of their sides below
  // it: coplanar tops, concave corners, edges at every angle. The tops' depths below a point
  // differ in their last bits, so which top is the shallower flips as the point moves
  std::mt19937 random(11);
  std::uniform_real_distribution<double> angle(-3.14159, 3.14159), offset(-0.006, 0.006);
  const Mat3 tilt = rotation_rpy(0.15, 0.1, 0.0);
  Object o;
  o.name = "union";
  o.type = ObjectType::boxes;
  o.first_box = 0;
  for (int i = 0; i < 6; ++i) {
    const Mat3 yaw = rotation_rpy(0.0, 0.0, angle(random));
    const Mat3 r{tilt * yaw.c0, tilt * yaw.c1, tilt * yaw.c2};
    const double half_z = 0.003 + 0.0004 * i;
    m.boxes.push_back({Vec3{0, 0, 0.01} + tilt * Vec3{offset(random), offset(random), -half_z}, {0.008, 0.003, half_z}, r, 0x3f});
  }
  for (int i = 0; i < 2; ++i) {
    m.boxes.push_back({{offset(random), offset(random), 0.004}, {0.002, 0.002, 0.002}, rotation_rpy(0.3 * angle(random), 0.2, angle(random)), 0x3f});
  }
  o.box_count = static_cast<int>(m.boxes.size());
  m.objects.push_back(o);
  m.index_boxes();
  // the default edge skin, and one wider than the near-box cache's margin
  for (double skin_m : {0.001, 0.003}) {
    Model with_skin = m;
    touch_all(with_skin, 0, skin_m);
    const Coverage c = compare(with_skin, models::Walk({-0.012, -0.012, 0.004}, {0.012, 0.012, 0.016}, 3), 400000);
    EXPECT_GT(c.held, c.contact_steps / 10) << skin_m;
    EXPECT_GT(c.tied, c.contact_steps / 20) << skin_m;
  }
}

TEST(HeldFace, AFloorOfMoreThan64TilesMatchesTheFullTest) {
  Model m;
  m.set_rate(5000.0);
  models::add_body(m, {0.0, 0.0, 0.02});
  // 9 x 8 flush tiles of 4 mm, their tops at 10 mm but one in five 1 mm lower (pits): seams
  // where two or four coplanar tops meet (of tiles of different thickness)
  std::vector<std::pair<Vec3, Vec3>> tiles;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 8; ++j) {
      const double top = (i * 7 + j * 3) % 5 == 0 ? 0.009 : 0.010, bottom = 0.0007 * ((i + 2 * j) % 4);
      tiles.push_back({{0.004 * (i - 4), 0.004 * (j - 3.5), (top + bottom) / 2}, {0.002, 0.002, (top - bottom) / 2}});
    }
  }
  const int floor = models::add_boxes(m, "tiles", tiles);
  ASSERT_GT(m.objects[floor].box_count, 64);
  m.index_boxes();
  touch_all(m, floor);
  const Coverage c = compare(m, models::Walk({-0.014, -0.012, 0.007}, {0.014, 0.012, 0.013}, 5), 150000);
  EXPECT_GT(c.held, c.contact_steps / 5);
  EXPECT_GT(c.tied, c.contact_steps / 20);
}

}  // namespace
}  // namespace enact::physics
