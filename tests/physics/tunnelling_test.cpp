// Tunnelling through the bridge's walls at the device's extremes (ERGOS: 60 N continuous,
// 1.8 m/s): a closed loop with a simulated device mass driven into a wall, and a kinematic
// drive straight through the wall, at 1 kHz and 5 kHz.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/devices/device_profile.h"
#include "tests/physics/models.h"

namespace enact::physics {
namespace {

// the body approaching the middle segment's wall along its horizontal normal
struct Approach {
  Model model;
  models::Segment segment;
  Vec3 direction;        // horizontal, towards the wall and on through it
  double half_width_m;   // the wall's near face is at lateral -half_width, the far face at +half_width
  double reach_m;        // the grid's extent from its centre along the direction
  int bridge = -1;

  // the body centre's coordinate along the direction, from the segment's centreline
  double lateral(const Vec3& centre) const { return dot(centre - segment.middle, direction); }
  // a centre at `lateral`, at height z
  Vec3 at(double lateral_m, double z_m) const {
    Vec3 c = segment.middle + direction * lateral_m;
    c.z = z_m;
    return c;
  }
  // lateral of the centre when the leading grid mass is `gap` outside the near face
  double outside(double gap_m) const { return -half_width_m - reach_m - gap_m; }
};

Approach approach(double rate_hz) {
  Approach a{models::bridge(rate_hz, "CM1"), {}, {}, 0.0, 0.0, -1};
  a.segment = models::bridge_segment(a.model, 1);
  a.direction = a.segment.across;
  a.bridge = a.model.find_object("bridge");
  a.half_width_m = a.model.objects[a.bridge].path.width_m / 2.0;
  a.reach_m = models::grid_reach(a.model, a.direction);
  return a;
}

// a force never points on through the wall (rounding of the rotated face normals allowed)
bool pushes_back_or_not_at_all(const Vec3& force, const Vec3& direction) { return dot(force, direction) <= 1e-9 * norm(force); }

class Tunnelling : public ::testing::TestWithParam<double> {};

// the device (moving mass, physical damping b) pushed by the hand at its continuous maximum,
// arriving at its maximum speed, grid 6 mm below the top; semi-implicit Euler for the device
TEST_P(Tunnelling, ClosedLoopAtTheDeviceExtremesIsHeldByTheEntryFace) {
  const devices::DeviceProfile ergos = *devices::find_device_profile("ergos");
  const Approach a = approach(GetParam());
  const double dt = a.model.dt_s;
  const Vec3 hand = a.direction * ergos.continuous_force_n;  // 60 N
  Vec3 x = a.at(a.outside(0.003), 0.006);
  Vec3 v = a.direction * ergos.max_speed_m_per_s;  // 1.8 m/s
  State s = make_state(a.model);
  models::place_body(a.model, s, x);
  int pulled = 0, contact_steps = 0;
  double max_lateral = a.lateral(x);
  for (int n = 0; n < 2000; ++n) {
    s.proxy_position_m[0] = x;
    step(a.model, s);
    const Vec3 force = s.proxy_force_n[0];
    contact_steps += norm(force) > 0.0;
    pulled += !pushes_back_or_not_at_all(force, a.direction);
    v += (hand + force - v * ergos.damping_n_s_per_m) * (dt / ergos.moving_mass_kg);
    x += v * dt;
    max_lateral = std::max(max_lateral, a.lateral(x));
  }
  EXPECT_GT(contact_steps, 0);
  EXPECT_EQ(pulled, 0) << "steps with a force towards the far side";
  // 6 mm below the top the wall holds: a mass rides over an edge only within edge_skin_m of it
  EXPECT_LT(max_lateral, a.half_width_m) << "the body centre passed the far face";
  // equilibrium against the hand, the leading mass held between the entry face and its depth below the top
  const double final_lateral = a.lateral(x);
  EXPECT_LT(norm(v), 0.01);
  EXPECT_LT(norm(hand + s.proxy_force_n[0]), 1.0);
  EXPECT_GT(final_lateral, a.outside(0.0));
  EXPECT_LT(final_lateral, a.outside(0.0) + 0.006);
}

// the body driven straight through the whole wall at 1.8 m/s: every grid mass entered through
// the near face, so no force ever points on towards the far side, even past the midline
TEST_P(Tunnelling, KinematicDriveThroughTheWallIsNeverPushedOn) {
  const Approach a = approach(GetParam());
  const double speed = 1.8, dt = a.model.dt_s;
  for (const double z : {0.002, 0.006}) {
    SCOPED_TRACE(z);
    State s = make_state(a.model);
    double lateral = a.outside(0.003);
    models::place_body(a.model, s, a.at(lateral, z));
    int pulled = 0, pushed_back = 0, held_past_midline = 0;
    const Proxy& p = a.model.proxies[0];
    while (lateral < a.half_width_m + a.reach_m + 0.003) {
      lateral += speed * dt;
      s.proxy_position_m[0] = a.at(lateral, z);
      step(a.model, s);
      const Vec3 force = s.proxy_force_n[0];
      pulled += !pushes_back_or_not_at_all(force, a.direction);
      pushed_back += dot(force, a.direction) < -1.0;
      for (int i = 0; i < p.rows * p.cols; ++i) {
        const int point = p.first_body + i;
        held_past_midline += s.in_contact[point] && a.lateral(s.x[point]) > 0.0;
      }
    }
    EXPECT_EQ(pulled, 0) << "steps with a force towards the far side";
    EXPECT_GT(pushed_back, 0);
    EXPECT_GT(held_past_midline, 0) << "the drive never took a mass in contact past the midline";
    EXPECT_EQ(s.faults, 0u);
  }
}

INSTANTIATE_TEST_SUITE_P(Rates, Tunnelling, ::testing::Values(1000.0, 5000.0),
                         [](const auto& p) { return std::to_string(static_cast<int>(p.param)) + "Hz"; });

}  // namespace
}  // namespace enact::physics
