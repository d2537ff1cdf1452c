// Test models built in code and their errors against analytic solutions, for
// `enact bench physics`: an undamped and a damped oscillator, a bouncing mass, a chain.
#include "nodes/enact/physics_reference.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "core/physics/state.h"

namespace enact::cli::reference {

namespace {

using physics::Integrator;
using physics::Model;
using math::Vec3;

// the test oscillator and the bouncing mass
constexpr double kMass_kg = 0.01;
constexpr double kOmega_rad_per_s = 2.0 * std::numbers::pi * 50.0;
constexpr double kAmplitude_m = 1e-3;
constexpr double kHorizon_s = 1.0;
constexpr double kZeta = 0.05;
constexpr double kGravity_m_per_s2 = 9.81;
constexpr double kDropHeight_m = 0.005;
constexpr double kContactStiffness_n_per_m = 2000.0;

// ---- scenes built in code ----

physics::Point fixed_point(const std::string& name, const Vec3& position_m) {
  physics::Point p;
  p.name = name;
  p.kind = physics::PointKind::fixed;
  p.position_m = position_m;
  return p;
}

physics::Point mass_point(const std::string& name, double mass_kg, const Vec3& position_m) {
  physics::Point p = fixed_point(name, position_m);
  p.kind = physics::PointKind::dynamic;
  p.mass_kg = mass_kg;
  return p;
}

physics::Link spring_damper(int a, int b, double stiffness_n_per_m, double damping_n_s_per_m, double rest_length_m) {
  return {.name = "spring" + std::to_string(b),
          .type = physics::LinkType::spring_damper,
          .a = a,
          .b = b,
          .stiffness_n_per_m = stiffness_n_per_m,
          .damping_n_s_per_m = damping_n_s_per_m,
          .rest_length_m = rest_length_m};
}

}  // namespace

// a mass (point 0) at rest above an undamped plane at z = 0, under gravity
Model bounce(Integrator integrator, double rate_hz, bool passive) {
  Model m;
  m.name = "bounce";
  m.integrator = integrator;
  m.gravity_m_per_s2 = {0.0, 0.0, -kGravity_m_per_s2};
  m.points = {mass_point("ball", kMass_kg, {0.0, 0.0, kDropHeight_m})};
  physics::Object floor;
  floor.name = "floor";
  floor.type = physics::ObjectType::plane;
  floor.plane_normal = {0.0, 0.0, 1.0};
  m.objects = {floor};
  m.contacts = {{.point = 0, .object = 0, .stiffness_n_per_m = kContactStiffness_n_per_m, .passive = passive, .friction = {}}};
  m.set_rate(rate_hz);
  return m;
}

namespace {

// x of point 1 at steps 0 .. steps
std::vector<double> positions(const Model& m, std::size_t steps) {
  physics::State s = physics::make_state(m);
  std::vector<double> x{s.x[1].x};
  for (std::size_t n = 0; n < steps; ++n) {
    physics::step(m, s);
    x.push_back(s.x[1].x);
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

// the bouncing mass's energy in flight, m v^2 / 2 + m g (z(n) + z(n-1)) / 2 with v the state's
// velocity (x(n) - x(n-1)) / dt: what all three integrators keep exactly under gravity alone
double flight_energy_j(const physics::State& s) {
  return 0.5 * kMass_kg * math::dot(s.v[0], s.v[0]) + 0.5 * kMass_kg * kGravity_m_per_s2 * (s.x[0].z + s.x_prev[0].z);
}

}  // namespace

// a mass (point 1) on an isotropic spring to a fixed point at the origin, released at rest from A
Model oscillator(Integrator integrator, double rate_hz, double zeta) {
  const double k = kMass_kg * kOmega_rad_per_s * kOmega_rad_per_s;
  Model m;
  m.name = "oscillator";
  m.integrator = integrator;
  m.points = {fixed_point("anchor", {}), mass_point("mass", kMass_kg, {kAmplitude_m, 0.0, 0.0})};
  m.links = {spring_damper(0, 1, k, 2.0 * zeta * std::sqrt(k * kMass_kg), 0.0)};
  m.set_rate(rate_hz);
  return m;
}

// n masses 1 mm apart on undamped springs from a fixed point, stretched by 1 % and released
Model chain(int masses, double rate_hz) {
  constexpr double spacing_m = 1e-3;
  Model m;
  m.name = "chain";
  m.points = {fixed_point("anchor", {})};
  for (int i = 1; i <= masses; ++i) {
    m.points.push_back(mass_point("mass" + std::to_string(i), kMass_kg, {1.01 * spacing_m * i, 0.0, 0.0}));
    m.links.push_back(spring_damper(i - 1, i, 1000.0, 0.0, spacing_m));
  }
  m.set_rate(rate_hz);
  return m;
}

// ---- errors, computed outside the timing ----

std::size_t steps_in(double seconds, double rate_hz) { return static_cast<std::size_t>(std::lround(seconds * rate_hz)); }

OscillatorErrors undamped_errors(Integrator integrator, double rate_hz) {
  const Model m = oscillator(integrator, rate_hz, 0.0);
  const std::size_t steps = steps_in(kHorizon_s, rate_hz);
  const std::vector<double> x = positions(m, steps);
  OscillatorErrors e;
  // global error against A cos(w t)
  for (std::size_t n = 0; n < x.size(); ++n) {
    const double exact = kAmplitude_m * std::cos(kOmega_rad_per_s * static_cast<double>(n) * m.dt_s);
    e.global = std::max(e.global, std::abs(x[n] - exact) / kAmplitude_m);
  }
  // amplitude: the largest |x| over the last period
  const std::size_t last_period = steps - steps_in(2.0 * std::numbers::pi / kOmega_rad_per_s, rate_hz);
  std::size_t peak = last_period;
  for (std::size_t n = last_period; n < x.size(); ++n) peak = std::abs(x[n]) > std::abs(x[peak]) ? n : peak;
  e.amplitude = std::abs(std::abs(refined_extremum(x, peak)) - kAmplitude_m) / kAmplitude_m;
  // phase at the last zero crossing, frequency from the first to the last
  const std::vector<double> t = zero_crossings(x, m.dt_s);
  const double crossings = static_cast<double>(t.size());
  e.phase_rad = (crossings - 0.5) * std::numbers::pi - kOmega_rad_per_s * t.back();
  const double measured = std::numbers::pi * (crossings - 1.0) / (t.back() - t.front());
  const double predicted = predicted_omega(integrator, m.dt_s);
  e.freq_vs_predicted = measured / predicted - 1.0;
  e.freq_warping = predicted / kOmega_rad_per_s - 1.0;
  return e;
}

double damped_error(Integrator integrator, double rate_hz) {
  const Model m = oscillator(integrator, rate_hz, kZeta);
  const std::vector<double> x = positions(m, steps_in(kHorizon_s, rate_hz));
  const double root = std::sqrt(1.0 - kZeta * kZeta);
  const double wd = kOmega_rad_per_s * root;
  double error = 0.0;
  for (std::size_t n = 0; n < x.size(); ++n) {
    const double t = static_cast<double>(n) * m.dt_s;
    const double exact = kAmplitude_m * std::exp(-kZeta * kOmega_rad_per_s * t) * (std::cos(wd * t) + kZeta / root * std::sin(wd * t));
    error = std::max(error, std::abs(x[n] - exact) / kAmplitude_m);
  }
  return error;
}

BounceErrors bounce_errors(Integrator integrator, double rate_hz, long steps, bool passive) {
  const Model m = bounce(integrator, rate_hz, passive);
  physics::State s = physics::make_state(m);
  physics::step(m, s);
  const double e0 = flight_energy_j(s);
  BounceErrors r;
  // heights kept until the first impact is over; energy followed over every step in flight
  std::vector<double> z{s.x_prev[0].z, s.x[0].z};
  bool impact_over = false;
  for (long n = 1; n < steps; ++n) {
    physics::step(m, s);
    if (s.x[0].z > 0.0 && s.x_prev[0].z > 0.0) {
      r.energy_drift = (flight_energy_j(s) - e0) / e0;
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

namespace {

// one integrator at one rate stepping with the reference every `every` reference steps
struct SweepRun {
  Model model;
  physics::State state;
  std::size_t every = 1;
  double sum_squares = 0.0;
  SweepRow row;
};

// ns per step of a run alone, positions sampled beforehand
double time_run(const Model& m, const HandPath& hand, double duration_s) {
  const std::vector<Vec3> motion = sample(hand, duration_s, m.rate_hz);
  physics::State s = physics::make_state(m);
  const auto start = std::chrono::steady_clock::now();
  for (const Vec3& p : motion) {
    s.proxy_position_m[0] = p;
    physics::step(m, s);
  }
  const std::chrono::duration<double, std::nano> elapsed = std::chrono::steady_clock::now() - start;
  return elapsed.count() / static_cast<double>(std::max<std::size_t>(1, motion.size()));
}

}  // namespace

Model sweep_model(const Model& scene, const haptics::ComputerModel& cm, const Vec3& start, Integrator integrator, double rate_hz) {
  Model m = scene;
  m.integrator = integrator;
  m.set_rate(rate_hz);
  haptics::apply(cm, m);
  m.points[m.proxies[0].point].position_m = start;
  return m;
}

std::vector<Vec3> sample(const HandPath& hand, double duration_s, double rate_hz) {
  std::vector<Vec3> motion(steps_in(duration_s, rate_hz));
  for (std::size_t n = 0; n < motion.size(); ++n) motion[n] = hand(static_cast<double>(n + 1) / rate_hz);
  return motion;
}

std::vector<Vec3> reference_forces(const Model& scene, const haptics::ComputerModel& cm, const HandPath& hand, double duration_s,
                                   double rate_hz, double reference_hz) {
  const Model reference = sweep_model(scene, cm, hand(0.0), Integrator::cordis, reference_hz);
  physics::State ref = physics::make_state(reference);
  const std::size_t every = steps_in(1.0 / rate_hz, reference_hz);
  std::vector<Vec3> forces;
  forces.reserve(steps_in(duration_s, rate_hz));
  for (std::size_t k = 1; k <= steps_in(duration_s, reference_hz); ++k) {
    ref.proxy_position_m[0] = hand(static_cast<double>(k) / reference_hz);
    physics::step(reference, ref);
    if (k % every == 0) forces.push_back(ref.proxy_force_n[0]);
  }
  return forces;
}

std::vector<SweepRow> rate_sweep(const Model& scene, const haptics::ComputerModel& cm, const HandPath& hand, double duration_s,
                                 double reference_hz) {
  const Vec3 start = hand(0.0);
  std::vector<SweepRun> runs;
  for (Integrator integrator : kIntegrators) {
    for (double rate_hz : kRates_hz) {
      SweepRun r;
      r.model = sweep_model(scene, cm, start, integrator, rate_hz);
      r.every = steps_in(1.0 / rate_hz, reference_hz);
      r.state = physics::make_state(r.model);
      r.row = {.integrator = integrator, .rate_hz = rate_hz};
      runs.push_back(std::move(r));
    }
  }
  const Model reference = sweep_model(scene, cm, start, Integrator::cordis, reference_hz);
  physics::State ref = physics::make_state(reference);
  // in lockstep: each run steps when its instant comes, and is compared with the reference then
  const std::size_t steps = steps_in(duration_s, reference_hz);
  for (std::size_t k = 1; k <= steps; ++k) {
    const Vec3 p = hand(static_cast<double>(k) / reference_hz);
    ref.proxy_position_m[0] = p;
    physics::step(reference, ref);
    const std::uint32_t ref_pins = haptics::pins(cm, reference, ref);
    for (SweepRun& r : runs) {
      if (k % r.every != 0) continue;
      r.state.proxy_position_m[0] = p;
      physics::step(r.model, r.state);
      const double error = math::norm(r.state.proxy_force_n[0] - ref.proxy_force_n[0]);
      r.sum_squares += error * error;
      r.row.force_max_error_n = std::max(r.row.force_max_error_n, error);
      r.row.pins_mismatch_fraction += haptics::pins(cm, r.model, r.state) != ref_pins ? 1.0 : 0.0;
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

void print_sweep(const std::vector<SweepRow>& rows, const char* title) {
  std::printf("\n%s\n%-16s %6s %9s %12s %12s %10s %7s\n", title, "integrator", "kHz", "ns/step", "F rms N", "F max N", "pins diff", "faults");
  for (const SweepRow& r : rows) {
    std::printf("%-16s %6.0f %9.1f %12.3e %12.3e %10.2e %7llu\n", physics::to_string(r.integrator), r.rate_hz / 1e3, r.ns_per_step,
                r.force_rms_error_n, r.force_max_error_n, r.pins_mismatch_fraction, static_cast<unsigned long long>(r.faults));
  }
}

void sweep_json(Json& j, const std::vector<SweepRow>& rows) {
  j.begin_array();
  for (const SweepRow& r : rows) {
    j.begin_object().field("integrator", physics::to_string(r.integrator)).field("rate_hz", r.rate_hz).field("ns_per_step", r.ns_per_step);
    j.field("force_rms_error_n", r.force_rms_error_n).field("force_max_error_n", r.force_max_error_n);
    j.field("pins_mismatch_fraction", r.pins_mismatch_fraction).field("faults", static_cast<long long>(r.faults)).end_object();
  }
  j.end_array();
}

}  // namespace enact::cli::reference
