#pragma once
// The components of a graph, built from node parameters: the simulator, the force-feedback
// device driver and the tactile device driver. The same objects run in their own processes
// (wired by the bus) or together in the co-located real-time container (wired by calls).
#include <memory>
#include <string>
#include <vector>

#include "core/devices/device.h"
#include "core/graph/params.h"
#include "core/sim/simulator.h"

namespace enact::graph {

// simulator params: scene (required), rate_hz, model, tactile_period_s, tactile_mode, force,
// min_fall_s, min_recovery_s, end_progress
sim::SimParams sim_params(const Params& p);
extern const std::vector<std::string> kSimParams;

// force device: device (simulated, falcon), watchdog_s, ramp_s, reengage_s; simulated: profile (ergos,
// falcon), hand_path or subject (a virtual subject's file) with subject_seed and noise_seed,
// start_m, hand_stiffness_n_per_m, hand_damping_n_s_per_m; falcon:
// transport (usb, emulator), serial, firmware, homing_timeout_s, max_force_n, and with the
// emulator its hand (hand_path, start_m, hand_*). Wrapped in the safety layer (clamp, NaN,
// watchdog); configured, not yet active
std::unique_ptr<devices::ForceDevice> make_force_device(const Params& p);
extern const std::vector<std::string> kForceParams;

// tactile device: device (simulated, metec), rows, cols, rise_time_s; metec: transport (usb,
// emulator), serial, first_cell; configured, not yet active
std::unique_ptr<devices::TactileDevice> make_tactile_device(const Params& p);
extern const std::vector<std::string> kTactileParams;

}  // namespace enact::graph
