#pragma once
// The config structs of the device components and of the node processes' own plumbing, each
// field bound once to its parameter (node_params.cpp: force_bindings(), tactile_bindings(),
// ffd_node_bindings(), ...; param_binding.h): the table gives --help, the checks and `enact
// param`, and make_force_device / make_tactile_device (components.cpp) and the node
// components (core/node) read them through it.
#include <cstdint>
#include <limits>
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

// what a loop process has: enact-ffd (and enact-rt's own table)
struct LoopConfig {
  double rate_hz = 5000.0;
  double spin_us = -1.0;     // -1: sized from this machine's probe
  double duration_s = 0.0;   // 0: until SIGINT/SIGTERM
  bool lock_memory = false;
  int fifo_priority = 0;     // 0: normal scheduling
  // the time the loop ends, when it starts at start_ns (duration_s 0: INT64_MAX, never)
  std::int64_t end_ns(std::int64_t start_ns) const {
    return duration_s > 0.0 ? start_ns + static_cast<std::int64_t>(duration_s * 1e9) : std::numeric_limits<std::int64_t>::max();
  }
};

// the plumbing of the node processes: their peers' names, rates, the observers they wait for
struct SimNodeConfig {
  std::string loop_transport = "auto";  // the ffd <-> sim hop: auto, local or zeromq
  std::string ffd_node = "ffd";
  double scene_rate_hz = 60.0;
  int observers = 0;
};
struct FfdNodeConfig {
  LoopConfig loop;
  std::string loop_transport = "auto";
  std::string sim_node = "sim";
  std::string tactile_node = "tactile";
  int observers = 0;
};
struct RtConfig {
  LoopConfig loop;
  double scene_rate_hz = 60.0;
  double shown_rate_hz = 100.0;
  int observers = 0;  // outside the container, of ffd/state
};
struct TactileNodeConfig {
  std::string sim_node = "sim";
  double shown_rate_hz = 100.0;
  double watchdog_s = 0.25;
};

// the observers' (enact-logger / plugin logger, enact-foxglove / plugin foxglove); the node
// turns them into graph::LoggerOptions and foxglove::BridgeOptions
struct LoggerConfig {
  std::string output = "recording.mcap";
  std::string topics;  // comma-separated; empty: every topic
  std::string regex, exclude;
  std::string compression = "zstd";
  double chunk_duration_s = 1.0;
  double split_size_mb = 0.0, split_duration_s = 0.0;
  std::string attach;
  double wait_s = 10.0;
};
struct FoxgloveConfig {
  int port = 8765;
  std::string host = "127.0.0.1";
  double max_rate_hz = 100.0;
  std::string attach;
};

}  // namespace enact::graph
