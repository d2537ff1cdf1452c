#include "core/physics/stability.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "core/physics/contact.h"

namespace enact::physics {
namespace {

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

struct Element {
  std::string name;
  double k = 0.0;  // as counted in the bound: weight times the element's own
  double z = 0.0;
  double weight = 1.0;
};

// a deformable body's links on its mass i: its proxy link (the proxy is kinematic: once) and
// its grid links (between two masses: twice)
void body_elements(const Model& m, int i, std::vector<Element>& out) {
  const Point& p = m.points[i];
  if (p.proxy < 0 || p.kind != PointKind::dynamic) return;
  const Proxy& body = m.proxies[p.proxy];
  const DeformableBody& d = body.deformable;
  out.push_back({"the proxy link of '" + p.name + "'", d.proxy_stiffness_n_per_m, d.proxy_damping_n_s_per_m});
  const int r = (i - body.first_body) / body.cols, c = (i - body.first_body) % body.cols;
  const int neighbours = (r > 0) + (r + 1 < body.rows) + (c > 0) + (c + 1 < body.cols);
  for (int n = 0; n < neighbours; ++n) {
    out.push_back({"a grid link of '" + p.name + "'", 2.0 * d.grid_stiffness_n_per_m, 2.0 * d.grid_damping_n_s_per_m, 2.0});
  }
}

// every link and contact that can act on point i at once, at its peak stiffness: all its
// links, and the contacts with the object whose group of overlapping objects is stiffest
// (a point cannot be inside two objects whose volumes are disjoint). A link between two
// masses counts twice (Gershgorin: its diagonal and off-diagonal terms; two masses moving
// against each other stretch it twice as fast: a chain's alternating mode needs 4k < 4M)
std::vector<Element> elements_on(const Model& m, int i) {
  std::vector<Element> out;
  body_elements(m, i, out);
  for (const Link& l : m.links) {
    if (l.a != i && l.b != i) continue;
    const bool coupled = m.points[l.a].kind == PointKind::dynamic && m.points[l.b].kind == PointKind::dynamic;
    const double w = coupled ? 2.0 : 1.0;
    out.push_back({"link '" + l.name + "'", w * l.peak_stiffness_n_per_m(), w * l.damping_n_s_per_m, w});
  }
  std::vector<const ContactPair*> pairs;
  for (const ContactPair& c : m.contacts) {
    if (c.point == i) pairs.push_back(&c);
  }
  std::vector<Element> best;
  double best_demand = -1.0;
  for (const ContactPair* c : pairs) {
    std::vector<Element> group;
    double demand = 0.0;
    for (const ContactPair* o : pairs) {
      if (o != c && !objects_overlap(m, m.objects[c->object], m.objects[o->object])) continue;
      group.push_back({"contact of '" + m.points[i].name + "' with '" + m.objects[o->object].name + "'", o->stiffness_n_per_m, o->damping_n_s_per_m});
      demand += o->stiffness_n_per_m + 2.0 * o->damping_n_s_per_m / m.dt_s;
      // friction's anchor spring acts across the normal, the contact's spring along it: the pair
      // is at most as stiff as the stiffer of the two in any direction (and stiffest directions
      // of several pairs add up to no more than their sum), so only what the anchor spring
      // has beyond the contact's stiffness counts
      const double beyond = o->friction.stiffness_n_per_m - o->stiffness_n_per_m;
      if (beyond <= 0.0) continue;
      group.push_back({"friction of '" + m.points[i].name + "' with '" + m.objects[o->object].name + "'", beyond, 0.0});
      demand += beyond;
    }
    if (demand > best_demand) {
      best_demand = demand;
      best = group;
    }
  }
  out.insert(out.end(), best.begin(), best.end());
  return out;
}

// each deformable body's bound on the step: the least over its masses
void body_bounds(const Model& m, StabilityReport& report) {
  for (std::size_t pi = 0; pi < m.proxies.size(); ++pi) {
    if (!m.proxies[pi].deformable.enabled()) continue;
    BodyStability b;
    b.proxy = static_cast<int>(pi);
    b.step_s = m.dt_s;
    b.max_step_s = std::numeric_limits<double>::infinity();
    for (const MassStability& s : report.masses) {
      if (m.points[s.point].proxy != b.proxy) continue;
      const double bound = s.min_stable_rate_hz > 0.0 ? 1.0 / s.min_stable_rate_hz : std::numeric_limits<double>::infinity();
      if (bound < b.max_step_s || b.point < 0) {
        b.max_step_s = bound;
        b.point = s.point;
      }
      b.stable = b.stable && s.stable;
    }
    report.bodies.push_back(b);
  }
}

}  // namespace

bool StabilityReport::stable() const {
  for (const auto& m : masses) {
    if (!m.stable) return false;
  }
  return true;
}

bool StabilityReport::passive() const {
  for (const auto& d : devices) {
    if (!d.passive) return false;
  }
  return true;
}

StabilityReport analyze_stability(const Model& m, double device_b) {
  StabilityReport report;
  const double dt = m.dt_s;
  const bool explicit_scheme = m.integrator != Integrator::implicit_euler;
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const Point& p = m.points[i];
    if (p.kind != PointKind::dynamic) continue;
    MassStability s;
    s.point = static_cast<int>(i);
    double largest = -1.0, largest_weight = 1.0;
    for (const Element& e : elements_on(m, s.point)) {
      s.stiffness_n_per_m += e.k;
      s.damping_n_s_per_m += e.z;
      if (e.k > largest) {
        largest = e.k;
        largest_weight = e.weight;
        s.largest_element = e.name;
      }
    }
    s.demand = s.stiffness_n_per_m + 2.0 * s.damping_n_s_per_m / dt;
    s.limit = explicit_scheme ? 4.0 * p.mass_kg / (dt * dt) : std::numeric_limits<double>::infinity();
    s.stable = s.demand < s.limit;
    s.largest_stable_stiffness_n_per_m = std::max(0.0, s.limit - (s.demand - std::max(largest, 0.0))) / largest_weight;
    // 4 m f^2 - 2 z f - K > 0
    const double z = s.damping_n_s_per_m, k = s.stiffness_n_per_m, mass = p.mass_kg;
    s.min_stable_rate_hz = explicit_scheme ? (2.0 * z + std::sqrt(4.0 * z * z + 16.0 * mass * k)) / (8.0 * mass) : 0.0;
    report.masses.push_back(s);
  }
  body_bounds(m, report);
  if (device_b < 0.0) return report;
  for (std::size_t pi = 0; pi < m.proxies.size(); ++pi) {
    DevicePassivity d;
    d.proxy = static_cast<int>(pi);
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      const Point& p = m.points[i];
      if (p.kind != PointKind::kinematic || p.proxy != d.proxy || !p.feeds_device) continue;
      for (const Element& e : elements_on(m, static_cast<int>(i))) {
        d.stiffness_n_per_m += e.k;
        d.damping_n_s_per_m += e.z;
      }
    }
    // a deformable body: the device is tied to its masses by their proxy links alone
    const Proxy& body = m.proxies[pi];
    for (int i = 0; body.deformable.enabled() && i < body.rows * body.cols; ++i) {
      if (!m.points[body.first_body + i].feeds_device) continue;
      d.stiffness_n_per_m += body.deformable.proxy_stiffness_n_per_m;
      d.damping_n_s_per_m += body.deformable.proxy_damping_n_s_per_m;
    }
    d.device_damping_n_s_per_m = device_b;
    d.required_n_s_per_m = d.stiffness_n_per_m * dt / 2.0 + d.damping_n_s_per_m;
    d.passive = device_b > d.required_n_s_per_m || d.stiffness_n_per_m + d.damping_n_s_per_m == 0.0;
    d.largest_passive_stiffness_n_per_m = std::max(0.0, 2.0 * (device_b - d.damping_n_s_per_m) / dt);
    d.min_passive_rate_hz = device_b > d.damping_n_s_per_m ? d.stiffness_n_per_m / (2.0 * (device_b - d.damping_n_s_per_m))
                                                           : std::numeric_limits<double>::infinity();
    report.devices.push_back(d);
  }
  return report;
}

std::string instability_message(const Model& m, const StabilityReport& r) {
  for (const MassStability& s : r.masses) {
    if (s.stable) continue;
    const Point& p = m.points[s.point];
    return m.source + ":" + std::to_string(p.line) + ": mass '" + p.name + "' is unstable with " + to_string(m.integrator) +
           format(" at %.0f Hz: K + 2Z = %.4g N/m exceeds 4M = %.4g N/m", m.rate_hz, s.demand, s.limit) +
           "\n  fix: lower the stiffness of " + s.largest_element +
           format(" to below %.4g N/m, or run at %.0f Hz or more, or use integrator: implicit_euler", s.largest_stable_stiffness_n_per_m,
                  std::ceil(s.min_stable_rate_hz)) +
           " (--force runs it anyway)";
  }
  return {};
}

std::string passivity_message(const Model& m, const StabilityReport& r, const std::string& device) {
  for (const DevicePassivity& d : r.devices) {
    if (d.passive) continue;
    const Proxy& p = m.proxies[d.proxy];
    return m.source + ":" + std::to_string(p.line) + ": body '" + p.name + "' is not guaranteed passive on " + device +
           format(" at %.0f Hz: K T / 2 + B = %.4g N s/m exceeds the device damping b = %.4g N s/m", m.rate_hz,
                  d.required_n_s_per_m, d.device_damping_n_s_per_m) +
           format("\n  fix: keep the summed contact stiffness below %.4g N/m, or run at %.0f Hz or more",
                  d.largest_passive_stiffness_n_per_m, std::ceil(d.min_passive_rate_hz));
  }
  return {};
}

}  // namespace enact::physics
