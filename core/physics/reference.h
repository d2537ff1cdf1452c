#pragma once
// Reference models built in code, and their errors against analytic solutions (no artificial
// damping): an undamped and a damped oscillator, a bouncing mass, a chain, and the rate sweep
// of a scene against a high-rate reference. One implementation for `enact check --rate-sweep`,
// `enact bench physics` and the physics tests. Deterministic apart from the sweep's timing.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/physics/mesh.h"
#include "core/physics/model.h"
#include "core/physics/state.h"

namespace enact::physics::reference {

// the integrators and rates every comparison covers
inline constexpr std::array kIntegrators{Integrator::cordis, Integrator::symplectic_euler, Integrator::implicit_euler};
inline constexpr std::array kRates_hz{1000.0, 2000.0, 5000.0, 10000.0, 20000.0, 44000.0};
// the rate sweep's reference rates: multiples of every rate above (--quick: the smaller)
inline constexpr double kSweepReference_hz = 880000.0;
inline constexpr double kSweepQuickReference_hz = 440000.0;

// steps of a duration at a rate
std::size_t steps_in(double seconds, double rate_hz);

// ---- scenes built in code ----

// a point of any kind; returns its index (a kinematic one still needs its proxy set)
int add_point(Model& m, const std::string& name, PointKind kind, math::Vec3 position_m, double mass_kg = 0.0);
// a link of stiffness k (N/m) and damping z (N s/m) between points a and b; returns its index
int add_link(Model& m, const std::string& name, LinkType type, int a, int b, double k, double z);
// an infinite plane through point_m facing `normal`; returns its object index
int add_plane(Model& m, const std::string& name, math::Vec3 point_m, math::Vec3 normal);
// a contact pair of a point with an object, stiffness k (N/m), damping z (N s/m)
void add_contact(Model& m, int point, int object, double k, double z);

// a mass of 1D motion along x on an isotropic link (spring, or spring_damper when z > 0) to an
// anchor at the origin: a fixed point, or a proxy held still (its force is then observable)
struct Oscillator {
  Model model;
  int mass = 0;
  int anchor = 1;
};
Oscillator oscillator(Integrator integrator, double rate_hz, double mass_kg, double k, double z, double x0_m,
                      PointKind anchor = PointKind::fixed);

// the reference oscillator: 0.01 kg, f0 = 50 Hz, damping ratio zeta, released from 1 mm at rest
Oscillator oscillator_50hz(Integrator integrator, double rate_hz, double zeta);

// n masses 1 mm apart on undamped springs from a fixed point, stretched by 1 % and released
Model chain(int masses, double rate_hz);

// a 0.01 kg mass (point 0) at rest 5 mm above a 2000 N/m plane under gravity, the contact's
// damping damping_n_s_per_m; `passive`: an energy-consistent contact (ContactPair::passive)
Model bounce(Integrator integrator, double rate_hz, bool passive, double damping_n_s_per_m = 0.0);

// the mesh rows' height field (enact bench physics, the mesh tests): 1 mm bumps (one every
// 21 mm) on a 5 mm plateau over z = 0, a square of `cells` cells of cell_m a side centred on the
// origin. The bumps start `margin` cells in from the field's north-west corner: fields of one
// cell size and cells - 2 margin equal share their middle, vertex for vertex (margin 0, cells
// N of 60 mm / N: the 60 mm square refined; margin m, 15 mm cells: the 4-cell square grown by
// m cells on each side)
Mesh bumpy_field(int cells, double cell_m, int margin = 0);

// a mass's energy in flight under gravity g along -z, m v^2/2 + m g (z(n) + z(n-1))/2 with v the
// state's velocity (x(n) - x(n-1)) / dt: what the explicit schemes keep exactly in flight
double flight_energy_j(const State& s, int point, double mass_kg, double g);

// ---- errors against the analytic solutions ----

struct OscillatorErrors {
  double global = 0.0;
  double amplitude = 0.0;
  double phase_rad = 0.0;
  double freq_vs_predicted = 0.0;
  double freq_warping = 0.0;
};

struct BounceErrors {
  double peak_penetration = 0.0;  // relative, signed
  double energy_drift = 0.0;      // relative, signed, at the last step in flight
  double energy_drift_max = 0.0;  // relative, largest |E - E0| / E0
};

// the undamped reference oscillator over 1 s against A cos(w t)
OscillatorErrors undamped_errors(Integrator integrator, double rate_hz);
// the damped one (zeta 0.05): max |x - x_exact| / A over 1 s
double damped_error(Integrator integrator, double rate_hz);
// the bouncing mass (undamped contact) dropped, for `steps` steps; energy compared in flight
// (both samples above the plane)
BounceErrors bounce_errors(Integrator integrator, double rate_hz, long steps, bool passive);

// ---- the rate sweep ----

// one integrator at one rate along a hand path, against the reference
struct SweepRow {
  Integrator integrator = Integrator::cordis;
  double rate_hz = 0.0;
  double ns_per_step = 0.0;             // wall clock over the whole path, alone
  double force_rms_error_n = 0.0;       // |F - F_ref| over the steps, root mean square
  double force_max_error_n = 0.0;       // and largest
  double pins_mismatch_fraction = 0.0;  // share of steps whose pins differ from the reference's
  std::uint64_t faults = 0;             // divergence guard trips
};

// position of the hand (the scene's first body) at time t (s) from the start of the path
using HandPath = std::function<math::Vec3(double)>;
// the pins a model in a state raises (haptics::pins under a computer model)
using PinsOf = std::function<std::uint32_t(const Model&, const State&)>;

// the scene (its first body starting at the path's start; a computer model already applied:
// which masses feed the device) driven along `hand` for duration_s through each integrator at
// each rate; every step's device force and pins compared with those of a cordis run at
// reference_hz (a multiple of every rate) at the same instant, on the same path
std::vector<SweepRow> rate_sweep(const Model& scene, const PinsOf& pins, const HandPath& hand, double duration_s, double reference_hz);

// the scene (its computer model applied) at a rate through an integrator, its first body
// starting at `start`
Model sweep_model(const Model& scene, const math::Vec3& start, Integrator integrator, double rate_hz);
// the hand's positions at each step of a run at rate_hz: step n (from 0) at time (n + 1) / rate_hz
std::vector<math::Vec3> sample(const HandPath& hand, double duration_s, double rate_hz);
// the device force of the reference (cordis at reference_hz, a multiple of rate_hz) at each
// step of a run at rate_hz along `hand`: the instants rate_sweep compares
std::vector<math::Vec3> reference_forces(const Model& scene, const HandPath& hand, double duration_s, double rate_hz, double reference_hz);

}  // namespace enact::physics::reference
