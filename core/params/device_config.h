#pragma once
// The config structs of the device components, each field bound once to its parameter
// (node_params.cpp: force_bindings(), tactile_bindings(); param_binding.h): the table gives
// --help, the checks and `enact param`, and make_force_device / make_tactile_device
// (components.cpp) read them through it.
#include <string>

#include "core/devices/falcon/falcon_device.h"
#include "core/devices/inverse3/inverse3_device.h"
#include "core/devices/metec/metec_device.h"
#include "core/devices/safety.h"
#include "core/devices/simulated_force.h"
#include "core/devices/simulated_tactile.h"

namespace enact::graph {

// the force device: which one, and the parameters of each (those of another device or
// transport given are refused by make_force_device)
struct ForceConfig {
  std::string device = "simulated";         // simulated, falcon, dhd, hd or inverse3
  devices::SimulatedForceParams hand;       // the simulated device and an emulator's hand (start_m: start_position)
  std::string start_scene;                  // the scene whose body the end-effector starts at
  devices::SafetyParams safety;             // every device: the safety layer
  std::string transport = "usb";            // falcon, inverse3: usb or emulator
  devices::falcon::FalconParams falcon;     // falcon: serial, firmware, homing_timeout_s, max_force_n
  std::string library;                      // dhd, hd: the vendor's library (empty: its default)
  std::string device_name;                  // hd
  devices::inverse3::Inverse3Params inverse3;  // inverse3: port, events_port, device_id, origin_m
};

// the tactile device
struct TactileConfig {
  std::string device = "simulated";       // simulated or metec
  devices::SimulatedTactileParams cells;  // rows, cols, rise_time_s (both devices)
  std::string transport = "usb";          // metec: usb or emulator
  devices::metec::MetecParams metec;      // metec: serial, first_cell
};

}  // namespace enact::graph
