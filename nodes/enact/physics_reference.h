#pragma once
// Test models built in code and their errors against analytic solutions (no artificial
// damping), computed deterministically apart from the timing of `enact bench physics`.
#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "core/haptics/computer_model.h"
#include "core/physics/model.h"
#include "nodes/enact/json.h"

namespace enact::cli::reference {

// the integrators and rates every comparison covers
inline constexpr std::array kIntegrators{physics::Integrator::cordis, physics::Integrator::symplectic_euler, physics::Integrator::implicit_euler};
inline constexpr std::array kRates_hz{1000.0, 2000.0, 5000.0, 10000.0, 20000.0, 44000.0};
// the rate sweep's reference rates: multiples of every rate above (--quick: the smaller)
inline constexpr double kSweepReference_hz = 880000.0;
inline constexpr double kSweepQuickReference_hz = 440000.0;

// steps of a duration at a rate
std::size_t steps_in(double seconds, double rate_hz);

// a 0.01 kg mass on a spring_damper to a fixed point, f0 = 50 Hz, damping ratio zeta,
// released from 1 mm at rest
physics::Model oscillator(physics::Integrator integrator, double rate_hz, double zeta);

// n masses 1 mm apart on undamped springs from a fixed point, stretched by 1 % and released
physics::Model chain(int masses, double rate_hz);

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

// the undamped oscillator over 1 s against A cos(w t)
OscillatorErrors undamped_errors(physics::Integrator integrator, double rate_hz);
// the damped oscillator (zeta 0.05): max |x - x_exact| / A over 1 s
double damped_error(physics::Integrator integrator, double rate_hz);
// a 0.01 kg mass at rest 5 mm above an undamped 2000 N/m plane under gravity; `passive`: an
// energy-consistent contact (ContactPair::passive)
physics::Model bounce(physics::Integrator integrator, double rate_hz, bool passive);
// that mass dropped, for `steps` steps; energy compared in flight (both samples above the plane)
BounceErrors bounce_errors(physics::Integrator integrator, double rate_hz, long steps, bool passive);

// one integrator at one rate along a hand path, against the reference
struct SweepRow {
  physics::Integrator integrator = physics::Integrator::cordis;
  double rate_hz = 0.0;
  double ns_per_step = 0.0;             // wall clock over the whole path, alone
  double force_rms_error_n = 0.0;       // |F - F_ref| over the steps, root mean square
  double force_max_error_n = 0.0;       // and largest
  double pins_mismatch_fraction = 0.0;  // share of steps whose pins differ from the reference's
  std::uint64_t faults = 0;             // divergence guard trips
};

// position of the hand (the scene's first body) at time t (s) from the start of the path
using HandPath = std::function<math::Vec3(double)>;

// the scene at a rate through an integrator under computer model cm, its first body starting at `start`
physics::Model sweep_model(const physics::Model& scene, const haptics::ComputerModel& cm, const math::Vec3& start,
                           physics::Integrator integrator, double rate_hz);
// the hand's positions at each step of a run at rate_hz: step n (from 0) at time (n + 1) / rate_hz
std::vector<math::Vec3> sample(const HandPath& hand, double duration_s, double rate_hz);
// the device force of the reference (cordis at reference_hz, a multiple of rate_hz) at each
// step of a run at rate_hz along `hand`: the instants rate_sweep compares
std::vector<math::Vec3> reference_forces(const physics::Model& scene, const haptics::ComputerModel& cm, const HandPath& hand,
                                         double duration_s, double rate_hz, double reference_hz);

// the scene (its first body under computer model cm, starting at the path's start) driven
// along `hand` for duration_s through each integrator at each rate; every step's device
// force and pins compared with those of a cordis run at reference_hz (a multiple of every
// rate) at the same instant, on the same path
std::vector<SweepRow> rate_sweep(const physics::Model& scene, const haptics::ComputerModel& cm, const HandPath& hand,
                                 double duration_s, double reference_hz);
// the rows as a table on stdout under a title, and as a JSON array
void print_sweep(const std::vector<SweepRow>& rows, const char* title);
void sweep_json(Json& j, const std::vector<SweepRow>& rows);

}  // namespace enact::cli::reference
