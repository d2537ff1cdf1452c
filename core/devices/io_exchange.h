#pragma once
// The exchange between a device backend's I/O side (a USB exchange thread, a polling thread, a
// vendor's servo thread calling back into us) and the real-time loop, without locks (usb::Latest): the
// I/O side publishes each sample it reads and takes the force to send; the loop reads the
// newest sample and writes commands. The rules every such backend keeps:
// - read(): a device error (fault bit device_error, velocity zeroed) while not active, after
//   the device failed, or when the newest sample is older than stale_ns (the device or the
//   I/O side stopped): a silent device shows within stale_ns plus one read; workspace_limit
//   while the position is outside the profile's workspace.
// - command(): zero while not active, and when write() has not been called for
//   command_timeout_ns (the loop stalled: the device stops pushing on its own, beneath the
//   safety layer's watchdog); a NaN/Inf command is zero. Counts the zero commands taken while
//   inactive, so deactivate() can wait until one went out.
#include <atomic>
#include <cstdint>

#include "core/devices/device.h"
#include "core/devices/usb/latest.h"

namespace enact::devices {

// one reading of the device, in the enact frame and SI units
struct IoReading {
  std::int64_t time_ns = 0;
  math::Vec3 position_m;
  math::Vec3 velocity_m_per_s;
  std::uint32_t buttons = 0;
  bool valid = false;
};

class IoExchange {
 public:
  // forget everything: no sample, no command, inactive, not failed
  void reset(std::int64_t stale_ns, std::int64_t command_timeout_ns, std::int64_t now_ns) noexcept;

  // the real-time side
  bool read(std::int64_t now_ns, const DeviceProfile& profile, ForceSample& out) const noexcept;
  void write(const math::Vec3& force_n) noexcept;
  void set_active(bool active) noexcept;
  bool active() const noexcept { return active_.load(std::memory_order_relaxed); }

  // the I/O side (one thread)
  // the force to send now (enact frame, N)
  math::Vec3 command(std::int64_t now_ns) noexcept;
  void publish(const IoReading& reading) noexcept { reading_.store(reading); }
  // the device failed (unplugged, an API call failed): reads are device errors from now on
  void fail() noexcept { failed_.store(true); }
  bool failed() const noexcept { return failed_.load(); }
  // zero commands taken while inactive
  const std::atomic<std::uint64_t>& zeroed() const noexcept { return zeroed_; }
  // wait (polling, not real-time) until two zero commands were taken after now (so the
  // first has gone out to the device), the device failed, or timeout_ns passed
  void await_zero(std::int64_t timeout_ns) const noexcept;

 private:
  struct Force {
    math::Vec3 force_n;
    std::uint64_t count = 0;  // writes so far
  };
  usb::Latest<IoReading> reading_;
  usb::Latest<Force> force_;
  std::atomic<bool> active_{false};
  std::atomic<bool> failed_{false};
  std::atomic<std::uint64_t> zeroed_{0};
  std::int64_t stale_ns_ = 0;
  std::int64_t command_timeout_ns_ = 0;
  // the I/O side's own
  std::uint64_t seen_writes_ = 0;
  std::int64_t last_write_seen_ns_ = 0;
};

// whether p is inside the profile's workspace (bounds included)
bool inside_workspace(const DeviceProfile& profile, const math::Vec3& p) noexcept;

}  // namespace enact::devices
