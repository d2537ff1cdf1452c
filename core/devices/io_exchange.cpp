#include "core/devices/io_exchange.h"

#include <chrono>
#include <thread>

#include "core/rt/clock.h"

namespace enact::devices {

void IoExchange::reset(std::int64_t stale_ns, std::int64_t command_timeout_ns, std::int64_t now_ns) noexcept {
  stale_ns_ = stale_ns;
  command_timeout_ns_ = command_timeout_ns;
  reading_.store({});
  force_.store({});
  active_.store(false);
  failed_.store(false);
  seen_writes_ = 0;
  last_write_seen_ns_ = now_ns;
}

bool inside_workspace(const DeviceProfile& profile, const math::Vec3& p) noexcept {
  const math::Vec3& lo = profile.workspace_min_m;
  const math::Vec3& hi = profile.workspace_max_m;
  return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
}

bool IoExchange::read(std::int64_t now_ns, const DeviceProfile& profile, ForceSample& out) const noexcept {
  const IoReading r = reading_.load();
  out.time_ns = r.valid ? r.time_ns : now_ns;
  out.position_m = r.position_m;
  out.velocity_m_per_s = r.velocity_m_per_s;
  out.buttons = r.buttons;
  const bool stale = !r.valid || now_ns - r.time_ns > stale_ns_;
  if (!active() || failed_.load(std::memory_order_relaxed) || stale) {
    out.velocity_m_per_s = {};
    out.faults = bit(DeviceFault::device_error);
    return false;
  }
  out.faults = inside_workspace(profile, r.position_m) ? 0u : bit(DeviceFault::workspace_limit);
  return true;
}

void IoExchange::write(const math::Vec3& force_n) noexcept {
  const math::Vec3 f = math::finite(force_n) ? force_n : math::Vec3{};
  force_.store({f, force_.load().count + 1});
}

void IoExchange::set_active(bool active) noexcept {
  // a fresh activation starts from zero force
  if (active) force_.store({{}, force_.load().count});
  active_.store(active);
}

math::Vec3 IoExchange::command(std::int64_t now_ns) noexcept {
  const Force f = force_.load();
  if (f.count != seen_writes_) {
    seen_writes_ = f.count;
    last_write_seen_ns_ = now_ns;
  }
  if (!active()) {
    zeroed_.fetch_add(1);
    return {};
  }
  if (now_ns - last_write_seen_ns_ > command_timeout_ns_) return {};
  return f.force_n;
}

void IoExchange::await_zero(std::int64_t timeout_ns) const noexcept {
  const std::uint64_t before = zeroed_.load();
  const std::int64_t give_up = rt::now_ns() + timeout_ns;
  while (zeroed_.load() < before + 2 && !failed() && rt::now_ns() < give_up) std::this_thread::sleep_for(std::chrono::microseconds(200));
}

}  // namespace enact::devices
