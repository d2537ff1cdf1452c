#include "core/devices/inverse3/emulator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <set>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/devices/params_error.h"
#include "core/rt/clock.h"

namespace enact::devices::inverse3 {
namespace {

using nlohmann::json;

constexpr std::size_t kBacklog_bytes = 1 << 20;

// a vector as the service writes one
json json_of(const math::Vec3& v) { return {{"x", v.x}, {"y", v.y}, {"z", v.z}}; }

}  // namespace

struct Inverse3Emulator::Impl {
  Inverse3EmulatorParams params;
  mutable std::mutex mutex;  // the handle, the counters, the clients
  SimulatedForceDevice handle;
  std::int64_t tick_ns = 0;
  std::int64_t start_ns = 0;
  std::int64_t last_command_ns = 0;  // when the force acting now was commanded
  std::atomic<std::int64_t> stalled_until_ns{0};
  std::uint32_t buttons = 0;
  std::uint64_t messages = 0, bad = 0, updates = 0;
  int session_id = 0;
  std::set<net::ClientId> clients;
  std::set<net::ClientId> listeners;
  std::unique_ptr<net::WsServer> sim;
  std::unique_ptr<net::WsServer> events;

  explicit Impl(Inverse3EmulatorParams p) : params(std::move(p)), handle(params.handle) {}

  // the message: the state of every device (with config on the inventory)
  std::string state_message(std::int64_t now_ns, bool inventory) {
    ForceSample s;
    handle.read(now_ns, s);
    json device = {{"device_id", params.device_id},
                   {"state", {{"cursor_position", json_of(s.position_m + params.origin_m)}, {"cursor_velocity", json_of(s.velocity_m_per_s)}, {"current_cursor_force", json_of(handle.applied_force_n())}}},
                   {"status", {{"ready", true}, {"in_use", params.in_use}, {"started", true}, {"power_supply", true}, {"calibrated", true}}}};
    json grip = {{"device_id", "61548"}, {"state", {{"buttons", {{"a", (buttons & 1u) != 0}, {"b", (buttons & 2u) != 0}, {"c", (buttons & 4u) != 0}}}}}};
    if (inventory) device["config"] = {{"type", "inverse3"}, {"handedness", "right"}, {"basis", {{"permutation", "XYZ"}}}};
    json j = {{"inverse3", json::array({device})}, {"verse_grip", json::array({grip})}};
    if (inventory) j["session_id"] = session_id;
    ++updates;
    return j.dump();
  }

  // the force of a message for our device; false when it is not JSON, not for us, or a field
  // has the wrong type
  bool command(const std::string& text, math::Vec3& force_n) const {
    try {
      return read_command(text, force_n);
    } catch (const json::exception&) {
      return false;
    }
  }
  bool read_command(const std::string& text, math::Vec3& force_n) const {
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("inverse3") || !j["inverse3"].is_array()) return false;
    bool ours = false;
    for (const json& d : j["inverse3"]) {
      if (d.value("device_id", "") != params.device_id) continue;
      ours = true;
      const json v = d.value("commands", json::object()).value("set_cursor_force", json::object()).value("vector", json::object());
      force_n = {v.value("x", 0.0), v.value("y", 0.0), v.value("z", 0.0)};
    }
    return ours;
  }

  void opened(net::ClientId id) {
    std::lock_guard lock(mutex);
    clients.insert(id);
    ++session_id;
    sim->send(id, state_message(rt::now_ns(), true), false);
  }

  void received(net::ClientId id, const std::string& text) {
    // the device's next tick: one update per tick at most (later while the service stalls)
    const std::int64_t now = rt::now_ns();
    const std::int64_t next_tick = std::max(start_ns + ((now - start_ns) / tick_ns + 1) * tick_ns, stalled_until_ns.load());
    {
      std::lock_guard lock(mutex);
      ++messages;
      // a command acts for one tick: past it, the device idled
      if (last_command_ns > 0 && now > last_command_ns + tick_ns) handle.write(last_command_ns + tick_ns, {});
      math::Vec3 f;
      if (command(text, f)) {
        handle.write(now, f);
        last_command_ns = now;
      } else {
        ++bad;
      }
    }
    rt::sleep_until_ns(next_tick);
    std::string state;
    {
      std::lock_guard lock(mutex);
      state = state_message(next_tick, false);
    }
    sim->send(id, state, false);
  }
};

Inverse3Emulator::Inverse3Emulator(Inverse3EmulatorParams params) : impl_(std::make_unique<Impl>(std::move(params))) {
  Impl& i = *impl_;
  require(std::isfinite(i.params.tick_hz) && i.params.tick_hz > 0.0 && i.params.tick_hz <= 100000.0, "inverse3 emulator", "tick_hz", i.params.tick_hz, "(0, 100000] Hz (default 4000)");
  i.tick_ns = std::llround(1e9 / i.params.tick_hz);
  i.handle.configure();
  i.handle.activate();
  i.start_ns = rt::now_ns();
  net::WsHandlers sim;
  sim.on_open = [&i](net::ClientId id) { i.opened(id); };
  sim.on_close = [&i](net::ClientId id) {
    std::lock_guard lock(i.mutex);
    i.clients.erase(id);
  };
  sim.on_text = [&i](net::ClientId id, const std::string& text) { i.received(id, text); };
  net::WsHandlers events;
  events.on_open = [&i](net::ClientId id) {
    std::lock_guard lock(i.mutex);
    i.listeners.insert(id);
  };
  events.on_close = [&i](net::ClientId id) {
    std::lock_guard lock(i.mutex);
    i.listeners.erase(id);
  };
  i.sim = std::make_unique<net::WsServer>("127.0.0.1", i.params.port, "", sim, kBacklog_bytes);
  i.events = std::make_unique<net::WsServer>("127.0.0.1", i.params.events_port, "", events, kBacklog_bytes);
}

Inverse3Emulator::~Inverse3Emulator() {
  impl_->sim->stop();
  impl_->events->stop();
}

int Inverse3Emulator::port() const { return impl_->sim->port(); }
int Inverse3Emulator::events_port() const { return impl_->events->port(); }

void Inverse3Emulator::set_buttons(std::uint32_t buttons) {
  std::lock_guard lock(impl_->mutex);
  impl_->buttons = buttons;
}

void Inverse3Emulator::emit(const std::string& name, const std::string& level, const std::string& safety_type, const std::string& message) {
  json data = {{"device_family", "inverse"}, {"device_id", impl_->params.device_id}};
  if (!safety_type.empty()) data["safety_type"] = safety_type;
  const std::string text = json{{"name", name}, {"category", "device"}, {"level", level}, {"data", data}, {"message", message}}.dump();
  std::set<net::ClientId> listeners;
  {
    std::lock_guard lock(impl_->mutex);
    listeners = impl_->listeners;
  }
  for (const auto id : listeners) impl_->events->send(id, text, false);
}

void Inverse3Emulator::disconnect() {
  std::set<net::ClientId> clients;
  {
    std::lock_guard lock(impl_->mutex);
    clients = impl_->clients;
  }
  for (const auto id : clients) impl_->sim->close(id);
  emit("device-disconnected", "warning", "", "device lost (emulated)");
}

void Inverse3Emulator::stall(double duration_s) { impl_->stalled_until_ns.store(rt::now_ns() + std::llround(duration_s * 1e9)); }

math::Vec3 Inverse3Emulator::force_n() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->handle.applied_force_n();
}

math::Vec3 Inverse3Emulator::handle_m() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->handle.true_position_m();
}

std::uint64_t Inverse3Emulator::messages() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->messages;
}

std::uint64_t Inverse3Emulator::bad_messages() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->bad;
}

std::uint64_t Inverse3Emulator::updates() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->updates;
}

std::size_t Inverse3Emulator::connections() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->clients.size();
}

}  // namespace enact::devices::inverse3
