#pragma once
// The devices of a graph's components, built from node parameters: the force-feedback device
// and the tactile device (the simulator's parameters: graph::sim_params, node_params.h). The
// same objects run in their own processes (wired by the bus) or together in the co-located
// real-time container (wired by calls).
#include <memory>
#include <string>
#include <vector>

#include "core/devices/device.h"
#include "core/params/params.h"

namespace enact::graph {

// the force device of force_table() (declared here): simulated (profile, a scripted hand or a
// virtual subject), falcon (transport usb or emulator: serial, firmware, homing_timeout_s,
// max_force_n; the emulator's hand), dhd (library, profile), hd (library, device_name,
// profile) or inverse3 (transport usb: port, events_port, device_id; or emulator: the
// emulator's hand; origin_m, profile). Parameters of another device or transport are refused.
// Wrapped in the safety layer (clamp, NaN, watchdog); configured, not yet active
std::unique_ptr<devices::ForceDevice> make_force_device(const Params& p);
// what the safety layer of a device make_force_device made did, and the force it left the
// device with: the line both hosts of the force device print when it ends
std::string safety_summary(const devices::ForceDevice& device);
// the force device's line when the task's completion ended a run in simulated time (both hosts)
inline constexpr const char* kRunOverLine = "the task is completed: the run ends here (simulated time)";

// the tactile device of tactile_bindings() (declared here): simulated, or metec (transport,
// serial, first_cell); configured, not yet active
std::unique_ptr<devices::TactileDevice> make_tactile_device(const Params& p);

}  // namespace enact::graph
