#include "core/devices/inverse3/inverse3_device.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/config/format.h"
#include "core/devices/params_error.h"
#include "core/rt/clock.h"

namespace enact::devices::inverse3 {
namespace {

constexpr const char* kDevice = "inverse3";
constexpr const char* kProfileName = "enact";               // our session's name in the Haply Hub
constexpr std::int64_t kDeactivateWait_ns = 200'000'000;
constexpr std::int64_t kEventsPoll_ns = 50'000'000;

std::string address(const std::string& host, int port) { return host + ":" + std::to_string(port); }

}  // namespace

Inverse3ForceDevice::Inverse3ForceDevice(Inverse3Params params) : params_(std::move(params)) {}

Inverse3ForceDevice::~Inverse3ForceDevice() { close(); }

void Inverse3ForceDevice::close() noexcept {
  stop_.store(true);
  if (io_.joinable()) io_.join();
  if (events_thread_.joinable()) events_thread_.join();
  // the last word: zero force (the service idles the device anyway when commands stop)
  if (client_ && !device_id_.empty()) client_->send(force_command(device_id_, {}));
  client_.reset();
  events_client_.reset();
}

std::string Inverse3ForceDevice::fault() const {
  std::lock_guard lock(fault_mutex_);
  return fault_;
}

void Inverse3ForceDevice::stop_with(const std::string& why) noexcept {
  {
    std::lock_guard lock(fault_mutex_);
    if (fault_.empty()) fault_ = why;
  }
  exchange_.fail();
}

void Inverse3ForceDevice::configure() {
  close();
  configured_ = false;
  stop_.store(false);
  {
    std::lock_guard lock(fault_mutex_);
    fault_.clear();
  }
  const Inverse3Params& p = params_;
  require(p.port > 0 && p.port < 65536, kDevice, "port", p.port, "1 .. 65535 (default 10001)");
  require(p.events_port >= 0 && p.events_port < 65536, kDevice, "events_port", p.events_port, "0 (none) .. 65535 (default 10020)");
  require(std::isfinite(p.connect_timeout_s) && p.connect_timeout_s > 0.0 && p.connect_timeout_s <= 60.0, kDevice, "connect_timeout_s", p.connect_timeout_s, "(0, 60] s (default 2)");
  require(std::isfinite(p.reply_timeout_s) && p.reply_timeout_s > 0.0 && p.reply_timeout_s <= 1.0, kDevice, "reply_timeout_s", p.reply_timeout_s, "(0, 1] s (default 0.1)");
  require(std::isfinite(p.stale_s) && p.stale_s > 0.0 && p.stale_s <= 0.009, kDevice, "stale_s", p.stale_s, "(0, 0.009] s: faults must show within 10 ms (default 0.005)");
  require(math::finite(p.origin_m), kDevice, "origin_m", p.origin_m.x + p.origin_m.y + p.origin_m.z, "finite metres");
  const auto profile = devices::find_device_profile(p.profile);
  if (!profile) refuse(kDevice, "no device profile '" + p.profile + "'", "set profile to one of `enact devices --profiles` (inverse3)");
  profile_ = *profile;
  // the simulation channel and its inventory
  try {
    client_ = std::make_unique<net::WsClient>(p.host, p.port, p.connect_timeout_s);
  } catch (const std::runtime_error& e) {
    refuse(kDevice, std::string("the Haply Inverse Service does not answer: ") + e.what(),
           "start the service (the Haply Hub, or: systemctl start haply-inverse-service) and plug the Inverse3 in; or set port to the service's simulation port");
  }
  const auto inventory_text = client_->receive(std::llround(p.connect_timeout_s * 1e9));
  Update inventory;
  std::string why = "nothing within " + config::number(p.connect_timeout_s) + " s";
  if (!inventory_text || !parse_update(*inventory_text, inventory, why)) {
    client_.reset();
    refuse(kDevice, "the service at " + address(p.host, p.port) + " sent no device inventory (" + why + ")",
           "check that port is the Inverse Service's simulation channel (default 10001), not its HTTP or events port");
  }
  pick_device(inventory);
  // the events channel: optional
  if (p.events_port > 0) {
    try {
      events_client_ = std::make_unique<net::WsClient>(p.host, p.events_port, p.connect_timeout_s);
    } catch (const std::runtime_error& e) {
      std::fprintf(stderr, "inverse3: no events channel (%s): safety events will not be reported\n", e.what());
    }
  }
  exchange_.reset(std::llround(p.stale_s * 1e9), std::llround(kCommandTimeout_s * 1e9), rt::now_ns());
  updates_.store(0);
  events_.store(0);
  io_ = std::thread([this] { io_loop(); });
  if (events_client_) events_thread_ = std::thread([this] { events_loop(); });
  configured_ = true;
}

void Inverse3ForceDevice::pick_device(const Update& inventory) {
  std::string listed;
  const DeviceEntry* chosen = nullptr;
  for (const DeviceEntry& d : inventory.inverse3) {
    listed += (listed.empty() ? "" : ", ") + d.device_id;
    if (chosen == nullptr && (params_.device_id.empty() || d.device_id == params_.device_id)) chosen = &d;
  }
  if (chosen == nullptr) {
    client_.reset();
    if (listed.empty()) refuse(kDevice, "the Inverse Service lists no Inverse3", "plug the Inverse3 in and power it on (the Haply Hub shows it when the service sees it)");
    refuse(kDevice, "the Inverse Service lists no Inverse3 '" + params_.device_id + "' (it lists " + listed + ")", "set device_id to one of those, or leave it empty for the first");
  }
  if (chosen->in_use) {
    client_.reset();
    refuse(kDevice, "the Inverse3 " + chosen->device_id + " is in use by another session", "close the other program that drives it (a demo, the Haply Hub's test view), then start again");
  }
  if (!chosen->ready) {
    client_.reset();
    refuse(kDevice, "the Inverse3 " + chosen->device_id + " is not ready", "check its power supply and wait for the Haply Hub to show it ready, then start again");
  }
  device_id_ = chosen->device_id;
}

void Inverse3ForceDevice::io_loop() noexcept {
  const std::int64_t reply_timeout_ns = std::llround(params_.reply_timeout_s * 1e9);
  bool first = true;
  Update update;
  std::string why;
  while (!stop_.load()) {
    const math::Vec3 f = to_service_force(exchange_.command(rt::now_ns()));
    if (!client_->send(force_command(device_id_, f, first ? kProfileName : ""))) return stop_with("the connection to the service closed");
    first = false;
    const auto reply = client_->receive(reply_timeout_ns);
    if (!reply) return stop_with(client_->closed() ? "the connection to the service closed" : "the service did not answer within reply_timeout_s");
    if (!parse_update(*reply, update, why)) continue;
    for (const DeviceEntry& d : update.inverse3) {
      if (d.device_id != device_id_) continue;
      exchange_.publish({rt::now_ns(), to_enact(d.position_m, params_.origin_m), d.velocity_m_per_s, update.buttons, true});
      updates_.fetch_add(1);
    }
  }
}

void Inverse3ForceDevice::events_loop() noexcept {
  while (!stop_.load()) {
    const auto text = events_client_->receive(kEventsPoll_ns);
    if (!text && events_client_->closed()) {
      std::fprintf(stderr, "inverse3: the events channel closed: safety events are no longer reported\n");
      return;
    }
    Event e;
    if (!text || !parse_event(*text, e)) continue;
    events_.fetch_add(1);
    std::fprintf(stderr, "inverse3: service event %s (%s)%s%s\n", e.name.c_str(), e.level.c_str(), e.message.empty() ? "" : ": ", e.message.c_str());
    if (stops_device(e) && (e.device_id.empty() || e.device_id == device_id_)) stop_with("service event " + e.name + (e.safety_type.empty() ? "" : " (" + e.safety_type + ")"));
  }
}

void Inverse3ForceDevice::activate() {
  if (!configured_) refuse(kDevice, "activate before configure", "call configure() first");
  exchange_.set_active(true);
}

bool Inverse3ForceDevice::read(std::int64_t now_ns, ForceSample& out) noexcept { return exchange_.read(now_ns, profile_, out); }

void Inverse3ForceDevice::write(std::int64_t, const math::Vec3& force_n) noexcept { exchange_.write(force_n); }

void Inverse3ForceDevice::deactivate() noexcept {
  if (!exchange_.active()) return;
  exchange_.set_active(false);
  exchange_.await_zero(kDeactivateWait_ns);
}

}  // namespace enact::devices::inverse3
