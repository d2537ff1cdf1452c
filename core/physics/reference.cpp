// Reference models built in code and their errors against analytic solutions; the rate sweep.
#include "core/physics/reference.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/rt/clock.h"

namespace enact::physics::reference {

namespace {

using math::Vec3;

// the reference oscillator and the bouncing mass
constexpr double kMass_kg = 0.01;
constexpr double kOmega_rad_per_s = 2.0 * std::numbers::pi * 50.0;
constexpr double kAmplitude_m = 1e-3;
constexpr double kHorizon_s = 1.0;
constexpr double kZeta = 0.05;
constexpr double kGravity_m_per_s2 = 9.81;
constexpr double kDropHeight_m = 0.005;
constexpr double kContactStiffness_n_per_m = 2000.0;

}  // namespace

std::size_t steps_in(double seconds, double rate_hz) { return static_cast<std::size_t>(std::lround(seconds * rate_hz)); }

// ---- scenes built in code ----

int add_point(Model& m, const std::string& name, PointKind kind, Vec3 position_m, double mass_kg) {
  Point p;
  p.name = name;
  p.kind = kind;
  p.mass_kg = mass_kg;
  p.position_m = position_m;
  m.points.push_back(p);
  return static_cast<int>(m.points.size()) - 1;
}

int add_link(Model& m, const std::string& name, LinkType type, int a, int b, double k, double z) {
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

int add_plane(Model& m, const std::string& name, Vec3 point_m, Vec3 normal) {
  Object o;
  o.name = name;
  o.type = ObjectType::plane;
  o.plane_point_m = point_m;
  o.plane_normal = normal;
  m.objects.push_back(o);
  return static_cast<int>(m.objects.size()) - 1;
}

void add_contact(Model& m, int point, int object, double k, double z) { m.contacts.push_back({point, object, k, z, 0, 0, false, {}}); }

Oscillator oscillator(Integrator integrator, double rate_hz, double mass_kg, double k, double z, double x0_m, PointKind anchor) {
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

Oscillator oscillator_50hz(Integrator integrator, double rate_hz, double zeta) {
  const double k = kMass_kg * kOmega_rad_per_s * kOmega_rad_per_s;
  return oscillator(integrator, rate_hz, kMass_kg, k, 2.0 * zeta * std::sqrt(k * kMass_kg), kAmplitude_m);
}

Mesh bumpy_field(int cells, double cell_m, int margin) {
  std::vector<double> heights;
  for (int r = 0; r <= cells; ++r) {
    for (int c = 0; c <= cells; ++c) {
      heights.push_back(0.005 + 0.001 * std::sin((r - margin) * cell_m * 300.0) * std::sin((c - margin) * cell_m * 300.0));
    }
  }
  return heightfield_mesh(heights, cells + 1, cells + 1, cell_m, {0, 0, 0}, 0.0);
}

Model chain(int masses, double rate_hz) {
  constexpr double spacing_m = 1e-3;
  Model m;
  m.name = "chain";
  add_point(m, "anchor", PointKind::fixed, {});
  for (int i = 1; i <= masses; ++i) {
    add_point(m, "mass" + std::to_string(i), PointKind::dynamic, {1.01 * spacing_m * i, 0.0, 0.0}, kMass_kg);
    add_link(m, "spring" + std::to_string(i), LinkType::spring_damper, i - 1, i, 1000.0, 0.0);
    m.links.back().rest_length_m = spacing_m;
  }
  m.set_rate(rate_hz);
  return m;
}

Model bounce(Integrator integrator, double rate_hz, bool passive, double damping_n_s_per_m) {
  Model m;
  m.name = "bounce";
  m.integrator = integrator;
  m.set_rate(rate_hz);
  m.gravity_m_per_s2 = {0.0, 0.0, -kGravity_m_per_s2};
  const int ball = add_point(m, "ball", PointKind::dynamic, {0.0, 0.0, kDropHeight_m}, kMass_kg);
  add_contact(m, ball, add_plane(m, "floor", {}, {0.0, 0.0, 1.0}), kContactStiffness_n_per_m, damping_n_s_per_m);
  m.contacts[0].passive = passive;
  return m;
}

double flight_energy_j(const State& s, int point, double mass_kg, double g) {
  return 0.5 * mass_kg * math::dot(s.v[point], s.v[point]) + 0.5 * mass_kg * g * (s.x[point].z + s.x_prev[point].z);
}

// ---- errors, computed outside any timing ----

namespace {

// x of the oscillator's mass at steps 0 .. steps
std::vector<double> positions(const Oscillator& o, std::size_t steps) {
  State s = make_state(o.model);
  std::vector<double> x{s.x[o.mass].x};
  for (std::size_t n = 0; n < steps; ++n) {
    step(o.model, s);
    x.push_back(s.x[o.mass].x);
  }
  return x;
}

// the vertex of the parabola through y[i-1], y[i], y[i+1] (y[i] at the ends or when flat)
double refined_extremum(const std::vector<double>& y, std::size_t i) {
  if (i == 0 || i + 1 >= y.size()) return y[i];
  const double curvature = y[i + 1] - 2.0 * y[i] + y[i - 1];
  const double slope = y[i + 1] - y[i - 1];
  return curvature == 0.0 ? y[i] : y[i] - slope * slope / (8.0 * curvature);
}

// times of the sign changes of x, interpolated linearly between samples
std::vector<double> zero_crossings(const std::vector<double>& x, double dt_s) {
  std::vector<double> t_s;
  for (std::size_t n = 0; n + 1 < x.size(); ++n) {
    if ((x[n] > 0.0) != (x[n + 1] > 0.0)) t_s.push_back((static_cast<double>(n) + x[n] / (x[n] - x[n + 1])) * dt_s);
  }
  return t_s;
}

// the discrete angular frequency the recurrence x(n+1) = 2x(n) - x(n-1) - w^2 dt^2 x(n)
// (explicit) or (M + K) x(n+1) = 2M x(n) - M x(n-1) (implicit) gives
double predicted_omega(Integrator integrator, double dt_s) {
  const double w_dt = kOmega_rad_per_s * dt_s;
  return (integrator == Integrator::implicit_euler ? std::atan(w_dt) : 2.0 * std::asin(w_dt / 2.0)) / dt_s;
}

}  // namespace

OscillatorErrors undamped_errors(Integrator integrator, double rate_hz) {
  const Oscillator o = oscillator_50hz(integrator, rate_hz, 0.0);
  const double dt_s = o.model.dt_s;
  const std::size_t steps = steps_in(kHorizon_s, rate_hz);
  const std::vector<double> x = positions(o, steps);
  OscillatorErrors e;
  // global error against A cos(w t)
  for (std::size_t n = 0; n < x.size(); ++n) {
    const double exact = kAmplitude_m * std::cos(kOmega_rad_per_s * static_cast<double>(n) * dt_s);
    e.global = std::max(e.global, std::abs(x[n] - exact) / kAmplitude_m);
  }
  // amplitude: the largest |x| over the last period
  const std::size_t last_period = steps - steps_in(2.0 * std::numbers::pi / kOmega_rad_per_s, rate_hz);
  std::size_t peak = last_period;
  for (std::size_t n = last_period; n < x.size(); ++n) peak = std::abs(x[n]) > std::abs(x[peak]) ? n : peak;
  e.amplitude = std::abs(std::abs(refined_extremum(x, peak)) - kAmplitude_m) / kAmplitude_m;
  // phase at the last zero crossing, frequency from the first to the last
  const std::vector<double> t = zero_crossings(x, dt_s);
  const double crossings = static_cast<double>(t.size());
  e.phase_rad = (crossings - 0.5) * std::numbers::pi - kOmega_rad_per_s * t.back();
  const double measured = std::numbers::pi * (crossings - 1.0) / (t.back() - t.front());
  const double predicted = predicted_omega(integrator, dt_s);
  e.freq_vs_predicted = measured / predicted - 1.0;
  e.freq_warping = predicted / kOmega_rad_per_s - 1.0;
  return e;
}

double damped_error(Integrator integrator, double rate_hz) {
  const Oscillator o = oscillator_50hz(integrator, rate_hz, kZeta);
  const std::vector<double> x = positions(o, steps_in(kHorizon_s, rate_hz));
  const double root = std::sqrt(1.0 - kZeta * kZeta);
  const double wd = kOmega_rad_per_s * root;
  double error = 0.0;
  for (std::size_t n = 0; n < x.size(); ++n) {
    const double t = static_cast<double>(n) * o.model.dt_s;
    const double exact = kAmplitude_m * std::exp(-kZeta * kOmega_rad_per_s * t) * (std::cos(wd * t) + kZeta / root * std::sin(wd * t));
    error = std::max(error, std::abs(x[n] - exact) / kAmplitude_m);
  }
  return error;
}

BounceErrors bounce_errors(Integrator integrator, double rate_hz, long steps, bool passive) {
  const Model m = bounce(integrator, rate_hz, passive);
  State s = make_state(m);
  step(m, s);
  const double e0 = flight_energy_j(s, 0, kMass_kg, kGravity_m_per_s2);
  BounceErrors r;
  // heights kept until the first impact is over; energy followed over every step in flight
  std::vector<double> z{s.x_prev[0].z, s.x[0].z};
  bool impact_over = false;
  for (long n = 1; n < steps; ++n) {
    step(m, s);
    if (s.x[0].z > 0.0 && s.x_prev[0].z > 0.0) {
      r.energy_drift = (flight_energy_j(s, 0, kMass_kg, kGravity_m_per_s2) - e0) / e0;
      r.energy_drift_max = std::max(r.energy_drift_max, std::abs(r.energy_drift));
    }
    if (impact_over) continue;
    z.push_back(s.x[0].z);
    impact_over = z.back() >= 0.0 && z[z.size() - 2] < 0.0;
  }
  // the first impact's deepest point against the elastic solution
  const double static_m = kMass_kg * kGravity_m_per_s2 / kContactStiffness_n_per_m;
  const double impact_speed2 = 2.0 * kGravity_m_per_s2 * kDropHeight_m;
  const double exact_m = static_m + std::sqrt(static_m * static_m + kMass_kg * impact_speed2 / kContactStiffness_n_per_m);
  const auto lowest = static_cast<std::size_t>(std::min_element(z.begin(), z.end()) - z.begin());
  r.peak_penetration = -refined_extremum(z, lowest) / exact_m - 1.0;
  return r;
}

// ---- the rate sweep ----

namespace {

// one integrator at one rate stepping with the reference every `every` reference steps
struct SweepRun {
  Model model;
  State state;
  std::size_t every = 1;
  double sum_squares = 0.0;
  SweepRow row;
};

// ns per step of a run alone, positions sampled beforehand
double time_run(const Model& m, const HandPath& hand, double duration_s) {
  const std::vector<Vec3> motion = sample(hand, duration_s, m.rate_hz);
  State s = make_state(m);
  const std::int64_t start_ns = rt::now_ns();
  for (const Vec3& p : motion) {
    s.proxy_position_m[0] = p;
    step(m, s);
  }
  const auto elapsed_ns = static_cast<double>(rt::now_ns() - start_ns);
  return elapsed_ns / static_cast<double>(std::max<std::size_t>(1, motion.size()));
}

}  // namespace

Model sweep_model(const Model& scene, const Vec3& start, Integrator integrator, double rate_hz) {
  Model m = scene;
  m.integrator = integrator;
  m.set_rate(rate_hz);
  m.points[m.proxies[0].point].position_m = start;
  return m;
}

std::vector<Vec3> sample(const HandPath& hand, double duration_s, double rate_hz) {
  std::vector<Vec3> motion(steps_in(duration_s, rate_hz));
  for (std::size_t n = 0; n < motion.size(); ++n) motion[n] = hand(static_cast<double>(n + 1) / rate_hz);
  return motion;
}

std::vector<Vec3> reference_forces(const Model& scene, const HandPath& hand, double duration_s, double rate_hz, double reference_hz) {
  const Model reference = sweep_model(scene, hand(0.0), Integrator::cordis, reference_hz);
  State ref = make_state(reference);
  const std::size_t every = steps_in(1.0 / rate_hz, reference_hz);
  std::vector<Vec3> forces;
  forces.reserve(steps_in(duration_s, rate_hz));
  for (std::size_t k = 1; k <= steps_in(duration_s, reference_hz); ++k) {
    ref.proxy_position_m[0] = hand(static_cast<double>(k) / reference_hz);
    step(reference, ref);
    if (k % every == 0) forces.push_back(ref.proxy_force_n[0]);
  }
  return forces;
}

std::vector<SweepRow> rate_sweep(const Model& scene, const PinsOf& pins, const HandPath& hand, double duration_s, double reference_hz) {
  const Vec3 start = hand(0.0);
  std::vector<SweepRun> runs;
  for (Integrator integrator : kIntegrators) {
    for (double rate_hz : kRates_hz) {
      SweepRun r;
      r.model = sweep_model(scene, start, integrator, rate_hz);
      r.every = steps_in(1.0 / rate_hz, reference_hz);
      r.state = make_state(r.model);
      r.row = {.integrator = integrator, .rate_hz = rate_hz};
      runs.push_back(std::move(r));
    }
  }
  const Model reference = sweep_model(scene, start, Integrator::cordis, reference_hz);
  State ref = make_state(reference);
  // in lockstep: each run steps when its instant comes, and is compared with the reference then
  const std::size_t steps = steps_in(duration_s, reference_hz);
  for (std::size_t k = 1; k <= steps; ++k) {
    const Vec3 p = hand(static_cast<double>(k) / reference_hz);
    ref.proxy_position_m[0] = p;
    step(reference, ref);
    const std::uint32_t ref_pins = pins(reference, ref);
    for (SweepRun& r : runs) {
      if (k % r.every != 0) continue;
      r.state.proxy_position_m[0] = p;
      step(r.model, r.state);
      const double error = math::norm(r.state.proxy_force_n[0] - ref.proxy_force_n[0]);
      r.sum_squares += error * error;
      r.row.force_max_error_n = std::max(r.row.force_max_error_n, error);
      r.row.pins_mismatch_fraction += pins(r.model, r.state) != ref_pins ? 1.0 : 0.0;
    }
  }
  std::vector<SweepRow> rows;
  for (SweepRun& r : runs) {
    const double n = static_cast<double>(std::max<std::size_t>(1, steps / r.every));
    r.row.force_rms_error_n = std::sqrt(r.sum_squares / n);
    r.row.pins_mismatch_fraction /= n;
    r.row.faults = r.state.faults;
    r.row.ns_per_step = time_run(r.model, hand, duration_s);
    rows.push_back(r.row);
  }
  return rows;
}

}  // namespace enact::physics::reference
