#include "core/devices/inverse3/protocol.h"

#include <nlohmann/json.hpp>

namespace enact::devices::inverse3 {
namespace {

using nlohmann::json;

math::Vec3 vec3(const json& j) { return {j.value("x", 0.0), j.value("y", 0.0), j.value("z", 0.0)}; }
json vec3(const math::Vec3& v) { return {{"x", v.x}, {"y", v.y}, {"z", v.z}}; }

std::uint32_t grip_buttons(const json& grip) {
  const json state = grip.value("state", json::object());
  if (state.contains("buttons") && state["buttons"].is_object()) {
    const json& b = state["buttons"];
    return (b.value("a", false) ? 1u : 0u) | (b.value("b", false) ? 2u : 0u) | (b.value("c", false) ? 4u : 0u);
  }
  return state.value("button", false) ? 1u : 0u;
}

// parse_update's work; throws json::exception on a field of the wrong type
bool read_update(const std::string& text, Update& out, std::string& why) {
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    why = "not JSON";
    return false;
  }
  if (!j.contains("inverse3") || !j["inverse3"].is_array()) {
    why = "no \"inverse3\" list";
    return false;
  }
  for (const json& d : j["inverse3"]) {
    DeviceEntry e;
    e.device_id = d.value("device_id", "");
    const json state = d.value("state", json::object());
    e.position_m = vec3(state.value("cursor_position", json::object()));
    e.velocity_m_per_s = vec3(state.value("cursor_velocity", json::object()));
    if (d.contains("status") && d["status"].is_object()) {
      e.has_status = true;
      e.ready = d["status"].value("ready", true);
      e.in_use = d["status"].value("in_use", false);
    }
    out.inverse3.push_back(e);
  }
  if (j.contains("verse_grip") && j["verse_grip"].is_array() && !j["verse_grip"].empty()) out.buttons = grip_buttons(j["verse_grip"][0]);
  return true;
}

// parse_event's work; throws json::exception on a field of the wrong type
bool read_event(const std::string& text, Event& out) {
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("name")) return false;
  const json data = j.value("data", json::object());
  out.name = j.value("name", "");
  out.level = j.value("level", "");
  out.message = j.value("message", "");
  out.device_id = data.is_object() ? data.value("device_id", "") : "";
  out.safety_type = data.is_object() ? data.value("safety_type", "") : "";
  return true;
}

}  // namespace

bool parse_update(const std::string& text, Update& out, std::string& why) {
  out = {};
  try {
    return read_update(text, out, why);
  } catch (const json::exception& e) {
    out = {};
    why = std::string("a field of the wrong type (") + e.what() + ")";
    return false;
  }
}

std::string force_command(const std::string& device_id, const math::Vec3& force_n, const std::string& profile) {
  json j = {{"inverse3", json::array({{{"device_id", device_id}, {"commands", {{"set_cursor_force", {{"vector", vec3(force_n)}}}}}}})}};
  if (!profile.empty()) j["session"] = {{"configure", {{"profile", {{"name", profile}}}}}};
  // a device id that is not UTF-8 (the service's to give) is sent with replacement characters, not thrown
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

bool parse_event(const std::string& text, Event& out) {
  try {
    return read_event(text, out);
  } catch (const json::exception&) {
    return false;
  }
}

bool stops_device(const Event& e) {
  return e.name == "device-disconnected" || e.name == "device-busy" || (e.name == "device-safety-triggered" && e.safety_type == "ebrake_triggered");
}

}  // namespace enact::devices::inverse3
