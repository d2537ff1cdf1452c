#pragma once
// Models built in code for the physics tests (one place for each layout), and the bridge
// scene with a computer model applied.
#include <cmath>
#include <string>
#include <vector>

#include "core/haptics/computer_model.h"
#include "core/physics/scene.h"
#include "core/physics/state.h"
#include "tests/support/test_util.h"

namespace enact::physics::models {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kPitch_m = 0.00245;  // Braille dot spacing, as in the bridge scene

// a point of any kind; kinematic points belong to proxy 0 with the given offset
inline int add_point(Model& m, const std::string& name, PointKind kind, Vec3 position_m, double mass_kg = 0.0) {
  Point p;
  p.name = name;
  p.kind = kind;
  p.mass_kg = mass_kg;
  p.position_m = position_m;
  m.points.push_back(p);
  return static_cast<int>(m.points.size()) - 1;
}

inline int add_link(Model& m, const std::string& name, LinkType type, int a, int b, double k, double z) {
  Link l;
  l.name = name;
  l.type = type;
  l.a = a;
  l.b = b;
  l.stiffness_n_per_m = k;
  l.damping_n_s_per_m = z;
  m.links.push_back(l);
  return static_cast<int>(m.links.size()) - 1;
}

// a mass of 1D motion along x on an isotropic link (spring, or spring_damper when z > 0) to an
// anchor at the origin: a fixed point, or a proxy held still (its force is then observable)
struct Oscillator {
  Model model;
  int mass = 0;
  int anchor = 1;
};

inline Oscillator oscillator(Integrator integrator, double rate_hz, double mass_kg, double k, double z, double x0_m,
                             PointKind anchor = PointKind::fixed) {
  Oscillator o;
  Model& m = o.model;
  m.name = "oscillator";
  m.source = "oscillator.yaml";
  m.integrator = integrator;
  m.set_rate(rate_hz);
  m.points.reserve(2);
  o.mass = add_point(m, "mass", PointKind::dynamic, {x0_m, 0, 0}, mass_kg);
  o.anchor = add_point(m, "anchor", anchor, {});
  if (anchor == PointKind::kinematic) {
    m.points[o.anchor].proxy = 0;
    m.proxies.push_back({"hand", o.anchor, -1, 0, 0, 0.0, 0});
  }
  add_link(m, "spring", z > 0.0 ? LinkType::spring_damper : LinkType::spring, o.anchor, o.mass, k, z);
  return o;
}

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

inline int add_plane(Model& m, const std::string& name, Vec3 point_m, Vec3 normal) {
  Object o;
  o.name = name;
  o.type = ObjectType::plane;
  o.plane_point_m = point_m;
  o.plane_normal = normal;
  m.objects.push_back(o);
  return static_cast<int>(m.objects.size()) - 1;
}

inline void add_contact(Model& m, int point, int object, double k, double z) { m.contacts.push_back({point, object, k, z, 0, 0, false, {}}); }

// the bridge scene at `rate_hz` with a computer model applied
inline Model bridge(double rate_hz, const std::string& computer_model = "CM1") {
  Model m = load_scene(enact::test::source_path("launch/scenes/bridge.yaml"));
  m.set_rate(rate_hz);
  haptics::apply(*haptics::preset(computer_model), m);
  return m;
}

inline Vec3 unit(const Vec3& v) { return v * (1.0 / norm(v)); }

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

// a mass's energy in flight under gravity g along -z, m v^2/2 + m g (z(n) + z(n-1))/2 with v the
// state's velocity (x(n) - x(n-1)) / dt: what the explicit schemes keep exactly in flight
inline double flight_energy_j(const State& s, int point, double mass_kg, double g) {
  return 0.5 * mass_kg * dot(s.v[point], s.v[point]) + 0.5 * mass_kg * g * (s.x[point].z + s.x_prev[point].z);
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

}  // namespace enact::physics::models
