#pragma once
// A message-level emulator of the Haply Inverse Service (protocol.h), for tests and for
// running enact without the device (`device: inverse3`, `transport: emulator`): WebSocket
// servers on loopback for the simulation channel and the events channel, speaking the
// service's messages as Haply documents them:
// - on connect, the inventory: session_id, one Inverse3 (config, state, status) and one
//   VerseGrip (its buttons in the 3.5 shape, "buttons": {a, b, c});
// - one state update per message received, at most one per device tick (tick_hz; Haply
//   gives "multi-kHz", the 4 kHz default is to check), so the client is paced at the rate
//   the device runs; a set_cursor_force acts for one tick, then the device idles (no force)
//   unless another arrives (Haply: control commands are "applied once and forgotten"; how
//   long the real device holds one is to check);
// - a message that is not JSON, or commands for another device_id, are counted and answered
//   with a state update all the same (what the real service does with them is to check);
// - events on the events channel: device-safety-triggered and any other, on demand;
//   disconnect() closes the simulation connections and emits device-disconnected.
// The handle is a simulated device (simulated_force.h, the "inverse3" profile by default)
// held by a scripted hand or a virtual subject, in the enact frame; positions go out in the
// service frame, origin_m added (the emulated device's mounting).
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "core/devices/simulated_force.h"
#include "core/net/ws_server.h"

namespace enact::devices::inverse3 {

struct Inverse3EmulatorParams {
  SimulatedForceParams handle = held_at_origin("inverse3");  // the handle's dynamics and the hand
  math::Vec3 origin_m{0.0, -0.14, 0.14};           // where enact's origin is in the service frame
  std::string device_id = "049D";
  double tick_hz = 4000.0;                         // (0, 100000]: the device's rate
  int port = 0;                                    // the simulation channel (0: a free port)
  int events_port = 0;                             // the events channel (0: a free port)
  bool in_use = false;                             // the device is taken by another session
};

class Inverse3Emulator {
 public:
  // configures the handle (config::Error on bad params) and starts both servers
  // (std::runtime_error when a port cannot be bound)
  explicit Inverse3Emulator(Inverse3EmulatorParams params);
  ~Inverse3Emulator();
  Inverse3Emulator(const Inverse3Emulator&) = delete;
  Inverse3Emulator& operator=(const Inverse3Emulator&) = delete;

  int port() const;
  int events_port() const;

  // the VerseGrip's buttons (bit 0: a, 1: b, 2: c)
  void set_buttons(std::uint32_t buttons);
  // an event on the events channel, about this device
  void emit(const std::string& name, const std::string& level, const std::string& safety_type, const std::string& message);
  // the device is lost: every simulation connection closed, device-disconnected emitted
  void disconnect();
  // the service stops answering for duration_s (a hung service): the commands that come
  // meanwhile are answered after it
  void stall(double duration_s);

  // the force acting on the handle now (enact frame, N), the handle's true position (enact frame)
  math::Vec3 force_n() const;
  math::Vec3 handle_m() const;
  // messages received, of them not JSON or for another device; state updates sent
  std::uint64_t messages() const;
  std::uint64_t bad_messages() const;
  std::uint64_t updates() const;
  // simulation connections open now
  std::size_t connections() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace enact::devices::inverse3
