// Sharp edges and corners of the bridge: the grid pressed 0.1 mm into the top and swept at
// 0.1 m/s (5 kHz) off the side edge, and along the centreline through a right-angle turn.
// The contact law bounds what the device can feel: no mass is deeper than its depth below the
// top, so |F| <= sum over masses in contact of (k depth + z speed), and F changes per step by
// at most 16 (k (depth + step) + 2 z speed); the top never pulls.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "tests/physics/models.h"

namespace enact::physics {
namespace {

constexpr double kRate_hz = 5000.0;
constexpr double kSpeed_m_per_s = 0.1;
constexpr double kPress_m = 0.0001;

struct Sweep {
  int steps = 0;
  int violations_magnitude = 0;  // |F| above the contact-law bound
  int violations_jump = 0;       // |F(n) - F(n-1)| above the bound
  int pulls = 0;                 // F_z < 0
  int max_in_contact = 0;
  int min_in_contact = 16;
  double max_force_n = 0.0;
};

// drive the body along a polyline of centre positions (z: pressed into the top) at constant speed
Sweep sweep(const std::vector<Vec3>& waypoints) {
  const Model m = models::bridge(kRate_hz, "CM1");
  const Proxy& p = m.proxies[0];
  const ContactPair& law = m.contacts[0];
  const double k = law.stiffness_n_per_m, z = law.damping_n_s_per_m;
  const double step_m = kSpeed_m_per_s * m.dt_s;
  const double jump_bound = 16.0 * (k * (kPress_m + step_m) + 2.0 * z * kSpeed_m_per_s);
  State s = make_state(m);
  models::place_body(m, s, waypoints.front());
  Sweep out;
  Vec3 previous_force;
  for (std::size_t w = 0; w + 1 < waypoints.size(); ++w) {
    const Vec3 from = waypoints[w], to = waypoints[w + 1];
    const int steps = static_cast<int>(norm(to - from) / step_m);
    for (int n = 1; n <= steps; ++n) {
      s.proxy_position_m[0] = from + (to - from) * (static_cast<double>(n) / steps);
      step(m, s);
      const Vec3 force = s.proxy_force_n[0];
      int in_contact = 0;
      for (int i = 0; i < p.rows * p.cols; ++i) in_contact += s.in_contact[p.first_body + i];
      const double bound = in_contact * (k * kPress_m + z * kSpeed_m_per_s);
      out.violations_magnitude += norm(force) > bound * (1.0 + 1e-9);
      out.violations_jump += out.steps > 0 && norm(force - previous_force) > jump_bound;
      out.pulls += force.z < 0.0;
      out.max_in_contact = std::max(out.max_in_contact, in_contact);
      out.min_in_contact = std::min(out.min_in_contact, in_contact);
      out.max_force_n = std::max(out.max_force_n, norm(force));
      previous_force = force;
      ++out.steps;
    }
  }
  EXPECT_EQ(s.faults, 0u);
  return out;
}

void expect_bounded(const Sweep& r) {
  EXPECT_GT(r.steps, 100);
  EXPECT_EQ(r.violations_magnitude, 0);
  EXPECT_EQ(r.violations_jump, 0);
  EXPECT_EQ(r.pulls, 0) << "the top pulled the body down";
}

double pressed_z(const Model& m) { return m.objects[m.find_object("bridge")].path.top_z_m - kPress_m; }

// from the middle of the middle segment, sideways off each side until the whole grid is off
TEST(Edges, SlidingOffTheSideEdge) {
  const Model m = models::bridge(kRate_hz);
  const models::Segment seg = models::bridge_segment(m, 1);
  const double off = m.objects[m.find_object("bridge")].path.width_m / 2.0 + models::grid_reach(m, seg.across) + 0.001;
  for (const double side : {1.0, -1.0}) {
    SCOPED_TRACE(side);
    Vec3 start = seg.middle, end = seg.middle + seg.across * (side * off);
    start.z = end.z = pressed_z(m);
    const Sweep r = sweep({start, end});
    expect_bounded(r);
    EXPECT_GE(r.max_in_contact, 12) << "the sweep starts on the top";
    EXPECT_EQ(r.min_in_contact, 0) << "the sweep ends off the top";
  }
}

// along the centreline from the middle of the first segment through the right-angle turn to
// the middle of the second
TEST(Edges, AlongTheCentrelineThroughARightAngleTurn) {
  const Model m = models::bridge(kRate_hz);
  const auto& line = m.objects[m.find_object("bridge")].path.centerline_m;
  std::vector<Vec3> path{models::bridge_segment(m, 0).middle, line[1], models::bridge_segment(m, 1).middle};
  for (Vec3& w : path) w.z = pressed_z(m);
  const Sweep r = sweep(path);
  expect_bounded(r);
  EXPECT_GE(r.min_in_contact, 12) << "the grid stays on the top";
}

}  // namespace
}  // namespace enact::physics
