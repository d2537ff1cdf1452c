#include <algorithm>
#include <cmath>
#include <limits>

#include "core/physics/contact.h"
#include "core/physics/state.h"

namespace enact::physics {
namespace {

// below this distance (m) a link with a rest length has no defined direction
constexpr double kMinDirection_m = 1e-12;
using math::kInfinity;
// added to a pair group's sphere: far above the rounding of a body point's position (m)
constexpr double kCullMargin_m = 1e-6;
// friction: a sliding point keeps sliding while its spring's pull grows by more than this
// fraction per step (far above the rounding of anchor positions, far below a step's slip)
constexpr double kSlideTolerance = 1e-9;

// the implicit integrator's per-point stiffness and damping (not needed by the explicit ones)
void add_stiffness(const Model& m, State& s, int i, double k, double z) {
  if (m.integrator != Integrator::implicit_euler) return;
  s.k_diag[i] += k;
  s.z_diag[i] += z;
}

// nonlinear spring force for elongation e, and its incremental stiffness
double nonlinear_force(const Link& l, double e, double& stiffness) {
  const double a = std::abs(e);
  if (a <= l.clip_elongation_m) {
    stiffness = l.stiffness_n_per_m + 3.0 * l.cubic_n_per_m3 * e * e;
    return l.stiffness_n_per_m * e + l.cubic_n_per_m3 * e * e * e;
  }
  const double ec = l.clip_elongation_m;
  stiffness = l.max_stiffness_n_per_m;
  const double at_clip = l.stiffness_n_per_m * ec + l.cubic_n_per_m3 * ec * ec * ec;
  return std::copysign(at_clip + l.max_stiffness_n_per_m * (a - ec), e);
}

// force on point a of a link (b gets the opposite); positive tension pulls a towards b
void link_force(const Model& m, const Link& l, State& s) {
  const Vec3 d = s.x[l.b] - s.x[l.a];
  const Vec3 dv = s.v[l.b] - s.v[l.a];
  const double dist = norm(d);
  Vec3 force;
  double k = 0.0;
  double z = 0.0;
  if (l.type == LinkType::contact) {
    // buttee: push only, while closer than the threshold
    if (dist >= l.threshold_m || dist < kMinDirection_m) return;
    const Vec3 u = d * (1.0 / dist);
    const double tension = std::min(0.0, l.stiffness_n_per_m * (dist - l.threshold_m) + l.damping_n_s_per_m * dot(dv, u));
    force = u * tension;
    k = l.stiffness_n_per_m;
    z = l.damping_n_s_per_m;
    s.in_contact[l.a] = s.in_contact[l.b] = 1;
  } else if (l.rest_length_m == 0.0) {
    // isotropic: f = k (xb - xa) + z (vb - va)
    k = l.type == LinkType::damper ? 0.0 : l.stiffness_n_per_m;
    z = l.type == LinkType::spring ? 0.0 : l.damping_n_s_per_m;
    if (l.type == LinkType::nonlinear_spring) {
      const double f = dist < kMinDirection_m ? 0.0 : nonlinear_force(l, dist, k);
      force = dist < kMinDirection_m ? Vec3{} : d * (f / dist);
    } else {
      force = d * k + dv * z;
    }
  } else {
    // along the link: f = k (|d| - l0) + z d'
    if (dist < kMinDirection_m) return;
    const Vec3 u = d * (1.0 / dist);
    const double e = dist - l.rest_length_m;
    double tension = 0.0;
    if (l.type == LinkType::nonlinear_spring) {
      tension = nonlinear_force(l, e, k);
    } else if (l.type != LinkType::damper) {
      k = l.stiffness_n_per_m;
      tension = k * e;
    }
    if (l.type == LinkType::damper || l.type == LinkType::spring_damper) {
      z = l.damping_n_s_per_m;
      tension += z * dot(dv, u);
    }
    force = u * tension;
  }
  s.f[l.a] += force;
  s.f[l.b] -= force;
  add_stiffness(m, s, l.a, k, z);
  add_stiffness(m, s, l.b, k, z);
}

// passivity observer: last step's spring work on the point, now that x(n) is known
void observe(const State& s, int point, ContactState& cs) {
  if (cs.spring_n == 0.0) return;
  cs.ledger_j -= 0.5 * cs.spring_n * dot(cs.normal, s.x[point] - cs.work_from_m);
  cs.spring_n = 0.0;
}

// Coulomb friction with stiction on a contact pushing with normal_n. The point is tied to an
// anchor on its tangent plane by a spring: the adhesion point of Hayward & Armstrong (2000), "A
// new computational model of friction applied to haptic rendering", which stays put while the
// spring holds and is dragged behind the point once it does not (no velocity is needed, and a
// point at rest does not drift). The spring holds up to static_coeff * normal_n; past that the
// anchor slides so that the spring pulls with dynamic_coeff * normal_n against the slip, and
// the dynamic limit holds until the point stops sliding (the stick/slip switch of Karnopp
// (1985), "Computer simulation of stick-slip friction in mechanical dynamic systems", taken on
// the spring's stretch instead of a band of velocity)
void friction_force(const Model& m, const ContactPair& c, State& s, ContactState& cs, double normal_n) {
  const Friction& fr = c.friction;
  const Vec3 x = s.x[c.point];
  if (!cs.anchored) {
    cs.anchor_m = x;
    cs.anchored = true;
    cs.sliding = false;
  }
  // the spring's stretch across the normal
  const Vec3 d = x - cs.anchor_m;
  Vec3 stretch = d - cs.normal * dot(cs.normal, d);
  const double k = fr.stiffness_n_per_m;
  const double pull_n = k * norm(stretch);
  // a sliding point that stopped (within rounding) sticks
  const double limit_n = cs.sliding ? fr.dynamic_coeff * normal_n * (1.0 + kSlideTolerance) : fr.static_coeff * normal_n;
  cs.sliding = pull_n > limit_n;
  if (cs.sliding) {
    stretch = stretch * (fr.dynamic_coeff * normal_n / pull_n);
  } else {
    add_stiffness(m, s, c.point, k, 0.0);
  }
  cs.anchor_m = x - stretch;
  s.f[c.point] -= stretch * k;
}

// unilateral visco-elastic contact of a point against a rigid object
void contact_force(const Model& m, const ContactPair& c, State& s) {
  ContactState& cs = s.contacts[&c - m.contacts.data()];
  if (c.passive) observe(s, c.point, cs);
  const double depth = update_contact(m, m.objects[c.object], s.x_prev[c.point], s.x[c.point], c.edge_skin_m, cs, s.hold);
  const double felt = depth - m.points[c.point].contact_threshold_m;
  // friction only while the contact pushes: a new push anchors afresh
  if (depth <= 0.0 || felt <= 0.0) cs.anchored = false;
  if (depth <= 0.0) return;
  s.in_contact[c.point] = 1;
  if (felt <= 0.0) return;
  // push only: damping may slow the separation but never pulls the point in
  const double spring = c.stiffness_n_per_m * felt;
  const double damper = c.damping_n_s_per_m * dot(s.v[c.point], cs.normal);
  const double push = std::max(0.0, spring - damper);
  s.f[c.point] += cs.normal * push;
  add_stiffness(m, s, c.point, c.stiffness_n_per_m, c.damping_n_s_per_m);
  if (c.friction.enabled()) friction_force(m, c, s, cs, push);
  if (!c.passive) return;
  cs.spring_n = spring;
  cs.damper_n = damper;
  cs.work_from_m = s.x_prev[c.point];
}

// one point's position and velocity after this step's forces; `gain`: how far x(n+1) moves
// per newton more on the point (m/N). A kinematic point is predicted at constant velocity
Vec3 advance(const Model& m, const State& s, int i, Vec3& v_next, double& gain) {
  const Point& p = m.points[i];
  const double dt = m.dt_s;
  const Vec3 x = s.x[i];
  if (p.kind != PointKind::dynamic) {
    gain = 0.0;
    v_next = s.v[i];
    return x + (x - s.x_prev[i]);
  }
  switch (m.integrator) {
    case Integrator::cordis: {
      gain = dt * dt / p.mass_kg;
      const Vec3 next = x * 2.0 - s.x_prev[i] + s.f[i] * (dt * dt / p.mass_kg);
      v_next = (next - x) * (1.0 / dt);
      return next;
    }
    case Integrator::symplectic_euler:
      gain = dt * dt / p.mass_kg;
      v_next = s.v[i] + s.f[i] * (dt / p.mass_kg);
      return x + v_next * dt;
    case Integrator::implicit_euler: {
      // (m + dt z + dt^2 k) v+ = m v + dt F + dt z v: stiffness and damping taken at the new state
      const double zd = s.z_diag[i];
      const double denom = p.mass_kg + dt * zd + dt * dt * s.k_diag[i];
      gain = dt * dt / denom;
      v_next = (s.v[i] * (p.mass_kg + dt * zd) + s.f[i] * dt) * (1.0 / denom);
      return x + v_next * dt;
    }
  }
  return x;
}

// the spring term that makes this step's spring work F . (x(n+1) - x(n-1)) / 2 equal to
// `energy_j`, x(n+1) moving by `gain` per newton of push; `travel_m`: that distance along the
// normal without this contact's push
double returning(double energy_j, double travel_m, double gain, double damper_n) {
  if (gain > 0.0) {
    const double b = travel_m - gain * damper_n;
    const double spring = (-b + std::sqrt(b * b + 8.0 * gain * energy_j)) / (2.0 * gain);
    if (spring >= damper_n) return spring;
  }
  return travel_m > 0.0 ? 2.0 * energy_j / travel_m : 0.0;
}

// passivity controller on the passive pairs, once every force of the step is known: the
// spring never returns more than its ledger holds, and on the step the point is predicted to
// leave the surface it returns exactly what the ledger holds (the sampled spring would return
// more or less, depending on where between two samples the point crossed the surface)
void control(const Model& m, State& s) {
  for (const int pair : s.passive) {
    ContactState& cs = s.contacts[pair];
    if (cs.spring_n == 0.0) continue;
    const ContactPair& c = m.contacts[pair];
    Vec3 v_next;
    double gain = 0.0;
    const Vec3 next = advance(m, s, c.point, v_next, gain);
    const double push = std::max(0.0, cs.spring_n - cs.damper_n);
    const double travel = dot(cs.normal, next - s.x_prev[c.point]);
    const bool leaving = cs.spring_n <= c.stiffness_n_per_m * dot(cs.normal, next - s.x[c.point]);
    if (!leaving && 0.5 * cs.spring_n * travel <= cs.ledger_j) continue;
    // never harder than the plain spring, or than the spring one step's travel deep: a
    // ledger grown over a long press is never released as a kick on the device
    const double cap = std::max(cs.spring_n, c.stiffness_n_per_m * std::abs(travel));
    cs.spring_n = std::min(cap, returning(std::max(0.0, cs.ledger_j), travel - gain * push, gain, cs.damper_n));
    s.f[c.point] += cs.normal * (std::max(0.0, cs.spring_n - cs.damper_n) - push);
  }
}

// a grid link of a deformable body between masses a and b: f = k (d - d_rest) + z d' on a
void grid_link(const Model& m, const DeformableBody& d, State& s, int a, int b) {
  const Vec3 rest = m.points[b].offset_m - m.points[a].offset_m;
  const Vec3 force = (s.x[b] - s.x[a] - rest) * d.grid_stiffness_n_per_m + (s.v[b] - s.v[a]) * d.grid_damping_n_s_per_m;
  s.f[a] += force;
  s.f[b] -= force;
  add_stiffness(m, s, a, d.grid_stiffness_n_per_m, d.grid_damping_n_s_per_m);
  add_stiffness(m, s, b, d.grid_stiffness_n_per_m, d.grid_damping_n_s_per_m);
}

// a deformable body's links, once its masses' contacts are known: each mass's contact force
// is kept, then its proxy link pulls it to its rest place on the proxy and its grid links to
// its right and lower neighbours'; the device feels the proxy links' reactions of the masses
// that feed it (the coupling force)
void body_links(const Model& m, const Proxy& body, State& s) {
  const DeformableBody& d = body.deformable;
  const int n = body.rows * body.cols;
  for (int q = body.first_body; q < body.first_body + n; ++q) s.body_contact_n[q] = s.f[q] - m.gravity_m_per_s2 * m.points[q].mass_kg;
  const Vec3 xp = s.x[body.point];
  const Vec3 vp = s.v[body.point];
  Vec3 coupling;
  for (int q = body.first_body; q < body.first_body + n; ++q) {
    const Vec3 force = (xp + m.points[q].offset_m - s.x[q]) * d.proxy_stiffness_n_per_m + (vp - s.v[q]) * d.proxy_damping_n_s_per_m;
    s.f[q] += force;
    if (m.points[q].feeds_device) coupling -= force;
    add_stiffness(m, s, q, d.proxy_stiffness_n_per_m, d.proxy_damping_n_s_per_m);
  }
  s.coupling_n[&body - m.proxies.data()] = coupling;
  for (int r = 0; r < body.rows; ++r) {
    for (int c = 0; c < body.cols; ++c) {
      const int q = body.first_body + r * body.cols + c;
      if (c + 1 < body.cols) grid_link(m, d, s, q, q + 1);
      if (r + 1 < body.rows) grid_link(m, d, s, q, q + body.cols);
    }
  }
}

void integrate(const Model& m, State& s) {
  double gain = 0.0;
  for (const int i : s.dynamic) {
    const Vec3 x = s.x[i];
    s.x[i] = advance(m, s, i, s.v[i], gain);
    s.x_prev[i] = x;
  }
}

// divergence guard: the first dynamic point that is not finite or runs away
Fault check(const Model& m, const State& s, int& point) {
  const double max_x2 = m.limits.max_position_m * m.limits.max_position_m;
  const double max_v2 = m.limits.max_speed_m_per_s * m.limits.max_speed_m_per_s;
  for (const int i : s.dynamic) {
    point = i;
    if (!finite(s.x[i]) || !finite(s.v[i])) return Fault::nonfinite_state;
    if (dot(s.x[i], s.x[i]) > max_x2) return Fault::runaway_position;
    if (dot(s.v[i], s.v[i]) > max_v2) return Fault::runaway_speed;
  }
  point = -1;
  return Fault::none;
}

void set_initial(const Model& m, State& s) {
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const Point& p = m.points[i];
    // body points (a rigid body's, or a deformable body's masses at rest) where the proxy is
    s.x[i] = p.proxy >= 0 ? s.proxy_position_m[p.proxy] + p.offset_m : p.position_m;
    s.v[i] = p.kind == PointKind::dynamic ? p.velocity_m_per_s : Vec3{};
    s.x_prev[i] = s.x[i] - s.v[i] * m.dt_s;
  }
  std::fill(s.contacts.begin(), s.contacts.end(), ContactState{});
}

void accumulate_forces(const Model& m, State& s) {
  std::fill(s.f.begin(), s.f.end(), Vec3{});
  std::fill(s.in_contact.begin(), s.in_contact.end(), std::uint8_t{0});
  if (m.integrator == Integrator::implicit_euler) {
    std::fill(s.k_diag.begin(), s.k_diag.end(), 0.0);
    std::fill(s.z_diag.begin(), s.z_diag.end(), 0.0);
  }
  for (const int i : s.dynamic) s.f[i] += m.gravity_m_per_s2 * m.points[i].mass_kg;
  for (const Link& l : m.links) link_force(m, l, s);
  for (std::size_t g = 0; g < s.groups.size(); ++g) {
    const PairGroup& group = s.groups[g];
    s.group_apart[g] = s.cull && apart(m, m.objects[group.object], s.proxy_position_m[group.proxy] + group.centre_offset_m, group.radius_m + kCullMargin_m);
  }
  for (const PairRun& run : s.runs) {
    const bool apart = run.group >= 0 && s.group_apart[run.group];
    for (int k = run.first; k < run.first + run.count; ++k) {
      if (!apart) {
        contact_force(m, m.contacts[k], s);
        continue;
      }
      // what update_contact would find: the point is in no box or mesh and above every plane
      // (a mesh's hold, planned inside, no longer holds)
      s.contacts[k].active = false;
      s.contacts[k].depth_m = 0.0;
      s.contacts[k].anchored = false;
      s.contacts[k].hold_r2 = 0.0;
    }
  }
  if (s.body_contact_n.empty()) return;
  for (const Proxy& body : m.proxies) {
    if (body.deformable.enabled()) body_links(m, body, s);
  }
}

// the pair groups of a model (one per device body and object, in order of first appearance)
// and the runs of pairs of one group
void group_pairs(const Model& m, State& s) {
  std::vector<int> group_of(m.contacts.size(), -1);
  for (std::size_t k = 0; k < m.contacts.size(); ++k) {
    const ContactPair& c = m.contacts[k];
    const Point& p = m.points[c.point];
    if (p.kind != PointKind::kinematic || c.passive) continue;
    int g = 0;
    while (g < static_cast<int>(s.groups.size()) && (s.groups[g].proxy != p.proxy || s.groups[g].object != c.object)) ++g;
    if (g == static_cast<int>(s.groups.size())) s.groups.push_back({p.proxy, c.object, {}, 0.0});
    group_of[k] = g;
  }
  for (std::size_t k = 0; k < m.contacts.size(); ++k) {
    if (s.runs.empty() || s.runs.back().group != group_of[k]) s.runs.push_back({static_cast<int>(k), 0, group_of[k]});
    ++s.runs.back().count;
  }
  // each group's sphere: around the middle of its points' offsets
  for (std::size_t g = 0; g < s.groups.size(); ++g) {
    Vec3 low{kInfinity, kInfinity, kInfinity}, high = -low;
    for (std::size_t k = 0; k < m.contacts.size(); ++k) {
      if (group_of[k] != static_cast<int>(g)) continue;
      const Vec3& o = m.points[m.contacts[k].point].offset_m;
      low = {std::min(low.x, o.x), std::min(low.y, o.y), std::min(low.z, o.z)};
      high = {std::max(high.x, o.x), std::max(high.y, o.y), std::max(high.z, o.z)};
    }
    PairGroup& group = s.groups[g];
    group.centre_offset_m = (low + high) * 0.5;
    for (std::size_t k = 0; k < m.contacts.size(); ++k) {
      if (group_of[k] == static_cast<int>(g)) group.radius_m = std::max(group.radius_m, norm(m.points[m.contacts[k].point].offset_m - group.centre_offset_m));
    }
  }
  s.group_apart.assign(s.groups.size(), 0);
}

void fault(const Model& m, State& s, Fault kind, int point) {
  ++s.faults;
  s.last_fault = kind;
  s.last_fault_point = point;
  set_initial(m, s);
  std::fill(s.proxy_force_n.begin(), s.proxy_force_n.end(), Vec3{});
}

}  // namespace

void Model::set_rate(double hz) {
  rate_hz = hz;
  dt_s = 1.0 / hz;
}

int Model::find_point(const std::string& n) const {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].name == n) return static_cast<int>(i);
  }
  return -1;
}

int Model::find_object(const std::string& n) const {
  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (objects[i].name == n) return static_cast<int>(i);
  }
  return -1;
}

void Model::make_deformable(int proxy, const DeformableBody& body) {
  Proxy& p = proxies[proxy];
  p.deformable = body;
  for (int i = 0; i < p.rows * p.cols; ++i) {
    Point& g = points[p.first_body + i];
    g.kind = PointKind::dynamic;
    g.mass_kg = body.mass_kg;
    g.line = body.line;
  }
}

State make_state(const Model& m) {
  State s;
  const std::size_t n = m.points.size();
  s.x.resize(n);
  s.x_prev.resize(n);
  s.v.resize(n);
  s.f.resize(n);
  s.in_contact.resize(n);
  s.k_diag.resize(n);
  s.z_diag.resize(n);
  s.contacts.resize(m.contacts.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (m.points[i].kind == PointKind::dynamic) s.dynamic.push_back(static_cast<int>(i));
    if (m.points[i].kind == PointKind::kinematic) s.kinematic.push_back(static_cast<int>(i));
  }
  for (std::size_t k = 0; k < m.contacts.size(); ++k) {
    if (m.contacts[k].passive) s.passive.push_back(static_cast<int>(k));
  }
  group_pairs(m, s);
  s.proxy_position_m.resize(m.proxies.size());
  s.proxy_force_n.resize(m.proxies.size());
  s.coupling_n.resize(m.proxies.size());
  for (std::size_t p = 0; p < m.proxies.size(); ++p) {
    s.proxy_position_m[p] = m.points[m.proxies[p].point].position_m;
    if (m.proxies[p].deformable.enabled()) s.body_contact_n.resize(n);
  }
  reset(m, s);
  return s;
}

void reset(const Model& m, State& s) {
  set_initial(m, s);
  s.steps = 0;
  s.time_s = 0.0;
  std::fill(s.proxy_force_n.begin(), s.proxy_force_n.end(), Vec3{});
  if (m.integrator != Integrator::cordis) return;
  // second-order start for the position recurrence: x(-1) = x0 - v0 dt + a0 dt^2 / 2
  accumulate_forces(m, s);
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const Point& p = m.points[i];
    if (p.kind == PointKind::dynamic) s.x_prev[i] += s.f[i] * (0.5 * m.dt_s * m.dt_s / p.mass_kg);
  }
  std::fill(s.contacts.begin(), s.contacts.end(), ContactState{});
}

void step(const Model& m, State& s) {
  const double dt = m.dt_s;
  // a non-finite device position is refused: the proxy holds its last position
  for (std::size_t p = 0; p < m.proxies.size(); ++p) {
    if (!finite(s.proxy_position_m[p])) {
      s.proxy_position_m[p] = s.x[m.proxies[p].point];
      ++s.faults;
      s.last_fault = Fault::nonfinite_input;
      s.last_fault_point = m.proxies[p].point;
    }
  }
  // kinematic points follow their proxies; velocities as backward differences
  const double rate = 1.0 / dt;
  for (const int i : s.kinematic) {
    const Point& p = m.points[i];
    const Vec3 before = s.x[i];
    const Vec3 now = s.proxy_position_m[p.proxy] + p.offset_m;
    s.x_prev[i] = before;
    s.x[i] = now;
    s.v[i] = (now - before) * rate;
  }
  accumulate_forces(m, s);
  if (!s.passive.empty()) control(m, s);
  // what each device feels: the forces on its proxy and body points that feed it
  for (std::size_t p = 0; p < m.proxies.size(); ++p) {
    Vec3 sum;
    for (const int i : s.kinematic) {
      if (m.points[i].proxy == static_cast<int>(p) && m.points[i].feeds_device) sum += s.f[i];
    }
    if (m.proxies[p].deformable.enabled()) sum += s.coupling_n[p];
    s.proxy_force_n[p] = sum;
  }
  integrate(m, s);
  ++s.steps;
  s.time_s = static_cast<double>(s.steps) * dt;
  int point = -1;
  Fault kind = check(m, s, point);
  for (std::size_t p = 0; kind == Fault::none && p < m.proxies.size(); ++p) {
    if (!finite(s.proxy_force_n[p])) {
      kind = Fault::nonfinite_state;
      point = m.proxies[p].point;
    }
  }
  if (kind != Fault::none) fault(m, s, kind, point);
}

const char* to_string(Fault fault) {
  switch (fault) {
    case Fault::none: return "none";
    case Fault::nonfinite_input: return "non-finite device position";
    case Fault::nonfinite_state: return "non-finite state";
    case Fault::runaway_position: return "runaway position";
    case Fault::runaway_speed: return "runaway speed";
  }
  return "?";
}

const char* to_string(Integrator integrator) {
  switch (integrator) {
    case Integrator::cordis: return "cordis";
    case Integrator::symplectic_euler: return "symplectic_euler";
    case Integrator::implicit_euler: return "implicit_euler";
  }
  return "?";
}

}  // namespace enact::physics
