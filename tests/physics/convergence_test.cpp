// Order of convergence of each integrator on an undamped oscillator: halving dt divides the
// global error against the analytic solution by 4 for cordis (position Verlet with a
// second-order start) and by 2 for the first-order symplectic and implicit Euler.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tests/physics/models.h"

namespace enact::physics {
namespace {

constexpr double kMass_kg = 0.01;
constexpr double kFrequency_hz = 20.0;
constexpr double kX0_m = 0.001;
constexpr double kHorizon_s = 0.5;

// max over the horizon of |x(n) - x0 cos(w n dt)|, released from rest at x0
double global_error(Integrator integrator, double rate_hz) {
  const double w = 2.0 * models::kPi * kFrequency_hz;
  const models::Oscillator o = models::oscillator(integrator, rate_hz, kMass_kg, kMass_kg * w * w, 0.0, kX0_m);
  State s = make_state(o.model);
  double error = 0.0;
  const auto steps = static_cast<int>(std::lround(kHorizon_s * rate_hz));
  for (int n = 1; n <= steps; ++n) {
    step(o.model, s);
    error = std::max(error, std::abs(s.x[o.mass].x - kX0_m * std::cos(w * n / rate_hz)));
  }
  return error;
}

// error ratios between successive halvings of dt, starting at `rate_hz`
void expect_order(Integrator integrator, double rate_hz, double low, double high) {
  const double e1 = global_error(integrator, rate_hz);
  const double e2 = global_error(integrator, 2.0 * rate_hz);
  const double e4 = global_error(integrator, 4.0 * rate_hz);
  EXPECT_GT(e2, 0.0);
  EXPECT_GT(e4, 0.0);
  EXPECT_GE(e1 / e2, low) << e1 << " " << e2;
  EXPECT_LE(e1 / e2, high) << e1 << " " << e2;
  EXPECT_GE(e2 / e4, low) << e2 << " " << e4;
  EXPECT_LE(e2 / e4, high) << e2 << " " << e4;
}

TEST(Convergence, CordisIsSecondOrder) { expect_order(Integrator::cordis, 2000.0, 3.2, 4.8); }

TEST(Convergence, SymplecticEulerIsFirstOrder) { expect_order(Integrator::symplectic_euler, 2000.0, 1.6, 2.4); }

// implicit Euler's amplitude decays as exp(-w^2 dt t / 2): at 2 kHz that is e^-2 over the
// horizon, far from the asymptotic regime, so its halvings start at 20 kHz (e^-0.2)
TEST(Convergence, ImplicitEulerIsFirstOrder) { expect_order(Integrator::implicit_euler, 20000.0, 1.6, 2.4); }

}  // namespace
}  // namespace enact::physics
