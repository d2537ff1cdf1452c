#pragma once
// The Haply Inverse Service's JSON messages that enact speaks (Haply's public documentation,
// docs.haply.co, Inverse SDK 3.x: "WebSocket Protocol", "Simulation Channel", "Control
// Commands", "Events & Monitoring"; no code copied):
// - simulation channel, ws://localhost:10001: on connect the service sends an inventory
//   (session_id; "inverse3": [{device_id, config, state, status}], "verse_grip": [...]); then
//   exactly one state update (the same shape, without config) per message the client sends,
//   so the client's sends pace the loop. A device's state holds cursor_position (m) and
//   cursor_velocity (m/s); its status holds ready, in_use, calibrated, ... (3.4 shape).
// - the force command: {"inverse3": [{"device_id": ID, "commands": {"set_cursor_force":
//   {"vector": {"x", "y", "z"}}}}]}, newtons, applied for one tick (stop sending: idle). The
//   first message may carry {"session": {"configure": {"profile": {"name": ...}}}}.
// - events channel, ws://localhost:10020, read-only: {"name", "category", "level", "data",
//   "message"}; e.g. device-safety-triggered (data.safety_type: ebrake_triggered, ...),
//   device-disconnected, device-busy.
// - VerseGrip buttons: state "button" (bool, 3.4) or "buttons" {"a", "b", "c"} (3.5).
// The service's frame ("application space") as enact reads it: metres, right-handed, x right,
// y away from the user, z up, with its origin at the device's base (TO CHECK on a device; the
// basis can be permuted in the service's configuration). enact's origin is `origin_m` there.
#include <cstdint>
#include <string>
#include <vector>

#include "core/math/vec3.h"

namespace enact::devices::inverse3 {

constexpr int kSimulationPort = 10001;
constexpr int kEventsPort = 10020;

// one Inverse3 as a message describes it
struct DeviceEntry {
  std::string device_id;
  math::Vec3 position_m;  // service frame
  math::Vec3 velocity_m_per_s;
  bool has_status = false;
  bool ready = true;
  bool in_use = false;
};

// what one inventory or state update says
struct Update {
  std::vector<DeviceEntry> inverse3;
  std::uint32_t buttons = 0;  // the first VerseGrip's buttons (bit 0: a / the button, 1: b, 2: c)
};

// parse an inventory or state update; false (and why) when it is not one, or a field has
// the wrong type (never throws)
bool parse_update(const std::string& text, Update& out, std::string& why);

// the force command for one device (force in the service frame, N); with the session's
// profile name on the first message when `profile` is not empty
std::string force_command(const std::string& device_id, const math::Vec3& force_n, const std::string& profile = "");

// an event of the events channel
struct Event {
  std::string name;
  std::string level;        // info, notice, warning, error, critical, panic
  std::string device_id;    // data.device_id, if any
  std::string safety_type;  // data.safety_type, if any
  std::string message;
};
// false when it is not an event (never throws)
bool parse_event(const std::string& text, Event& out);
// whether an event stops the device from rendering forces for us: the device was lost, its
// emergency brake engaged, or another session took it
bool stops_device(const Event& e);

// the enact position of a service-frame position, and the service-frame force of an enact force
constexpr math::Vec3 to_enact(const math::Vec3& service_m, const math::Vec3& origin_m) { return service_m - origin_m; }
constexpr math::Vec3 to_service_force(const math::Vec3& enact_n) { return enact_n; }

}  // namespace enact::devices::inverse3
