#pragma once
// Test models built in code and their errors against analytic solutions (no artificial
// damping), computed deterministically apart from the timing of `enact bench physics`.
#include <cstddef>

#include "core/physics/model.h"

namespace enact::cli::reference {

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

}  // namespace enact::cli::reference
