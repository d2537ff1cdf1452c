#pragma once
// Models built in code for the physics tests (one place for each layout), the bridge
// scene with a computer model applied, and the hand motions and measures they share.
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "core/haptics/computer_model.h"
#include "core/physics/contact.h"
#include "core/physics/reference.h"
#include "core/physics/scene.h"
#include "core/physics/state.h"
#include "core/sim/offline.h"
#include "tests/support/test_util.h"

namespace enact::physics::models {

// the scenes built in code that the references use too (core/physics/reference.h)
using reference::add_contact;
using reference::add_link;
using reference::add_plane;
using reference::add_point;
using reference::flight_energy_j;
using reference::Oscillator;
using reference::oscillator;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kPitch_m = 0.00245;  // Braille dot spacing, as in the bridge scene

// a device proxy at `centre` with a rows x cols grid of kinematic masses, laid out as a scene
// body: row 0 at +y, column 0 at -x, centred on the proxy
inline void add_body(Model& m, Vec3 centre, int rows = 4, int cols = 4) {
  Proxy proxy{"finger", -1, -1, rows, cols, kPitch_m, 0};
  proxy.point = add_point(m, "finger", PointKind::kinematic, centre);
  m.points[proxy.point].proxy = static_cast<int>(m.proxies.size());
  proxy.first_body = static_cast<int>(m.points.size());
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      Point g = m.points[proxy.point];
      g.name = grid_point_name(proxy.name, r, c);
      g.offset_m = {(c - (cols - 1) / 2.0) * kPitch_m, ((rows - 1) / 2.0 - r) * kPitch_m, 0.0};
      g.position_m = centre + g.offset_m;
      m.points.push_back(g);
    }
  }
  m.proxies.push_back(proxy);
}

// a rigid object made of axis-aligned boxes (centre, half extents); returns its index
inline int add_boxes(Model& m, const std::string& name, const std::vector<std::pair<Vec3, Vec3>>& boxes) {
  Object o;
  o.name = name;
  o.type = ObjectType::boxes;
  o.first_box = static_cast<int>(m.boxes.size());
  for (const auto& [centre, half] : boxes) m.boxes.push_back({centre, half, {}, 0x3f});
  o.box_count = static_cast<int>(boxes.size());
  m.objects.push_back(o);
  return static_cast<int>(m.objects.size()) - 1;
}

// a closed mesh object; returns its index
inline int add_mesh(Model& m, const std::string& name, Mesh mesh) {
  Object o;
  o.name = name;
  o.type = ObjectType::mesh;
  o.mesh = static_cast<int>(m.meshes.size());
  m.meshes.push_back(std::move(mesh));
  m.objects.push_back(o);
  return static_cast<int>(m.objects.size()) - 1;
}

// an axis-aligned box as 12 triangles (two per face, wound outwards)
inline Mesh box_mesh(Vec3 centre, Vec3 half) {
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) corners.push_back(centre + Vec3{i & 1 ? half.x : -half.x, i & 2 ? half.y : -half.y, i & 4 ? half.z : -half.z});
  return build_mesh(corners, {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 4, 6}, {0, 6, 2},
                              {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3}});
}

// a capsule (a sphere when the ends are equal) pushing a point on its axis along `axis_normal`
inline int add_capsule(Model& m, const std::string& name, Vec3 from_m, Vec3 to_m, double radius_m, Vec3 axis_normal) {
  Object o;
  o.name = name;
  o.type = ObjectType::capsule;
  o.axis_from_m = from_m;
  o.axis_to_m = to_m;
  o.radius_m = radius_m;
  o.axis_normal = axis_normal;
  m.objects.push_back(o);
  return static_cast<int>(m.objects.size()) - 1;
}

// what a fresh contact pair with object `o` finds at x (the full search, no hold): the depth
// and, in contact, the normal
struct Probe {
  double depth_m = 0.0;
  Vec3 normal;
};
inline Probe probe(const Model& m, int o, const Vec3& x) {
  ContactState c;
  const double depth = update_contact(m, m.objects[o], x, x, 0.001, c, false);
  return {depth, c.active ? c.normal : Vec3{}};
}

// friction on every contact pair of a model
inline void add_friction(Model& m, Friction friction) {
  for (ContactPair& c : m.contacts) c.friction = friction;
}

// the bridge scene at `rate_hz` with a computer model applied (`scene`: a variant of it)
inline Model bridge(double rate_hz, const std::string& computer_model = "CM1",
                    const std::string& scene = enact::test::source_path("launch/scenes/bridge.yaml")) {
  Model m = load_scene(scene);
  m.set_rate(rate_hz);
  haptics::apply(*haptics::preset(computer_model), m);
  return m;
}

inline Vec3 unit(const Vec3& v) { return v * (1.0 / norm(v)); }

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
inline bool same_bits(const Vec3& a, const Vec3& b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z); }

// a segment of the bridge's centreline: its middle (at the top), direction and horizontal normal
struct Segment {
  Vec3 middle;
  Vec3 along;
  Vec3 across;  // along rotated by -90 degrees about z
};

inline Segment bridge_segment(const Model& m, int i) {
  const auto& line = m.objects[m.find_object("bridge")].path.centerline_m;
  const Vec3 along = unit(line[i + 1] - line[i]);
  return {(line[i] + line[i + 1]) * 0.5, along, {along.y, -along.x, 0.0}};
}

// the farthest a grid mass reaches from the body's centre along a horizontal direction
inline double grid_reach(const Model& m, const Vec3& direction) {
  double reach = 0.0;
  const Proxy& p = m.proxies[0];
  for (int i = 0; i < p.rows * p.cols; ++i) reach = std::max(reach, dot(m.points[p.first_body + i].offset_m, direction));
  return reach;
}

// move the body to `centre` and start from rest there
inline void place_body(const Model& m, State& s, Vec3 centre) {
  s.proxy_position_m[0] = centre;
  reset(m, s);
}

// all per-point vectors finite
inline bool state_finite(const State& s) {
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (!finite(s.x[i]) || !finite(s.x_prev[i]) || !finite(s.v[i]) || !finite(s.f[i])) return false;
  }
  for (const Vec3& f : s.proxy_force_n) {
    if (!finite(f)) return false;
  }
  return true;
}

// a body wandering over [low, high]: smooth random accelerations, now and then a burst of
// speed (up to ~0.5 m/s) or a stop, bouncing off the region's walls
class Walk {
 public:
  Walk(Vec3 low, Vec3 high, unsigned seed) : low_(low), high_(high), random_(seed) { x_ = (low + high) * 0.5; }

  Vec3 next(double dt_s) {
    std::normal_distribution<double> noise(0.0, 1.0);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const double scale = uniform(random_) < 1e-3 ? 20.0 : 1.0;  // a burst
    v_ += Vec3{noise(random_), noise(random_), 0.5 * noise(random_)} * (2.0 * scale * dt_s);
    if (uniform(random_) < 2e-4) v_ = {};  // a stop: the hand rests
    const double speed = norm(v_);
    if (speed > 0.5) v_ = v_ * (0.5 / speed);
    x_ += v_ * dt_s;
    bounce(x_.x, v_.x, low_.x, high_.x);
    bounce(x_.y, v_.y, low_.y, high_.y);
    bounce(x_.z, v_.z, low_.z, high_.z);
    return x_;
  }

 private:
  static void bounce(double& x, double& v, double low, double high) {
    if (x < low) x = low, v = std::abs(v);
    if (x > high) x = high, v = -std::abs(v);
  }
  Vec3 low_, high_, x_, v_;
  std::mt19937 random_;
};

// the scripted hand path of the bridge scene (sim::scripted_path) sampled at `rate_hz`
inline std::vector<Vec3> scripted_motion(double rate_hz) {
  sim::SimParams p;
  p.scene = enact::test::source_path("launch/scenes/bridge.yaml");
  p.rate_hz = rate_hz;
  sim::Simulator simulator;
  simulator.configure(p);
  const task::Trajectory tr = sim::scripted_path(simulator);
  std::vector<Vec3> motion(static_cast<std::size_t>(std::lround((tr.end_s() - tr.start_s()) * rate_hz)));
  for (std::size_t n = 0; n < motion.size(); ++n) motion[n] = tr.at(tr.start_s() + static_cast<double>(n) / rate_hz);
  return motion;
}

// the work the contact forces do on device 0 moved along `path` (stepping `s`), the discrete
// work the integrators do: sum of F(n) . (x(n+1) - x(n-1)) / 2, with x(-1) = x(0). Positive: the
// model gave the device energy
inline double device_work_j(const Model& m, State& s, const std::vector<Vec3>& path) {
  double work = 0.0;
  for (std::size_t n = 0; n + 1 < path.size(); ++n) {
    s.proxy_position_m[0] = path[n];
    step(m, s);
    work += 0.5 * dot(s.proxy_force_n[0], path[n + 1] - path[n == 0 ? 0 : n - 1]);
  }
  return work;
}

// a walk over the whole bridge, from 2 mm above its top to 4 mm into it and off its sides onto
// the floor, then straight up out of every contact (no energy is left in a spring at the end)
inline std::vector<Vec3> walk_over_the_bridge(const Model& m, unsigned seed, double duration_s) {
  const auto& line = m.objects[m.find_object("bridge")].path.centerline_m;
  Walk walk({line[0].x - 0.012, line[0].y, 0.008}, {line[3].x + 0.012, line[3].y, 0.014}, seed);
  std::vector<Vec3> path;
  for (long n = 0; n < std::lround(duration_s * m.rate_hz); ++n) path.push_back(walk.next(m.dt_s));
  const Vec3 last = path.back();
  for (int n = 1; n <= 200; ++n) path.push_back({last.x, last.y, last.z + (0.03 - last.z) * n / 200.0});
  return path;
}

}  // namespace enact::physics::models
