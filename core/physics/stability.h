#pragma once
// Stability analysis at load time.
//  - Per dynamic mass, the discrete stability bound of the integrator at the model's rate.
//    Explicit schemes (cordis, symplectic_euler; the same recurrence): K + 2Z < 4M with
//    K = sum of stiffness, Z = sum of damping / dt, M = m / dt^2, summed over every link and
//    contact (with its friction's anchor spring, across the normal: the stiffer of the two)
//    that can act on the mass at once, a link between two masses twice (Gershgorin:
//    two masses moving against each other load it twice; von Neumann analysis of
//    x(n+1) = 2x(n) - x(n-1) - (K x(n) + Z (x(n) - x(n-1))) / M).
//    implicit_euler takes each mass's own stiffness and damping at the new state: its
//    per-mass recurrence (M + K) x(n+1) = (2M - K_o) x(n) - M x(n-1), with K_o <= K the
//    stiffness towards other moving masses, is stable for every K >= 0 (unconditional).
//  - Per device proxy, the passivity bound of Colgate & Schenkel (1997) for a device with
//    physical damping b sampled with period T: b > K T / 2 + B, with K and B the stiffness
//    and damping of every contact and link on the points feeding that device at once
//    (all grid masses in contact together).
#include <string>
#include <vector>

#include "core/physics/model.h"

namespace enact::physics {

struct MassStability {
  int point = -1;
  double stiffness_n_per_m = 0.0;   // K
  double damping_n_s_per_m = 0.0;   // sum of z
  double demand = 0.0;              // K + 2Z (N/m)
  double limit = 0.0;               // 4M (N/m); infinite for implicit_euler
  bool stable = true;
  std::string largest_element;      // the link or contact with the largest stiffness on it
  double largest_stable_stiffness_n_per_m = 0.0;  // for that element, others unchanged
  double min_stable_rate_hz = 0.0;  // the rate from which the mass is stable
};

struct DevicePassivity {
  int proxy = -1;
  double stiffness_n_per_m = 0.0;  // K: all contacts and links feeding the device together
  double damping_n_s_per_m = 0.0;  // B
  double required_n_s_per_m = 0.0; // K T / 2 + B
  double device_damping_n_s_per_m = 0.0;  // b of the device profile
  bool passive = true;
  double largest_passive_stiffness_n_per_m = 0.0;  // K that keeps b > K T / 2 + B
  double min_passive_rate_hz = 0.0;
};

// a deformable body (Proxy::deformable): the explicit schemes' bound K + 2Z < 4M solved for the
// step, h < 4m / (z + sqrt(z^2 + 4 K m)) (2 sqrt(m/K) undamped), K and z summed on each mass as
// above; the body's bound is its least, at its mass with the stiffest links for its mass
struct BodyStability {
  int proxy = -1;
  int point = -1;            // the mass that binds
  double max_step_s = 0.0;   // the bound on dt; infinite for implicit_euler
  double step_s = 0.0;       // the model's dt
  bool stable = true;
};

struct StabilityReport {
  std::vector<MassStability> masses;
  std::vector<BodyStability> bodies;     // deformable bodies only
  std::vector<DevicePassivity> devices;  // empty without a device damping
  bool stable() const;
  bool passive() const;
};

// device_damping_n_s_per_m < 0: no device passivity check
StabilityReport analyze_stability(const Model& model, double device_damping_n_s_per_m = -1.0);

// the first unstable mass as a message naming the element, the bound and the largest
// stable value (empty when stable)
std::string instability_message(const Model& model, const StabilityReport& report);
std::string passivity_message(const Model& model, const StabilityReport& report, const std::string& device);

}  // namespace enact::physics
