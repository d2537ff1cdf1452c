#pragma once
// A safety layer around any force device (a decorator, itself a ForceDevice):
// - write(): a NaN/Inf command becomes zero (counted, nonfinite_command bit); a command over
//   the inner profile's peak force is scaled down to it, direction kept (counted, clamped bit).
// - read(): the watchdog. When no write arrived within watchdog_s of now (strictly more than
//   watchdog_s since the last write), the force sent to the inner device ramps linearly from
//   the last command to zero over the next ramp_s, then stays zero (a zero write on every
//   read); the watchdog bit is set in the samples and the episode is counted once. A fresh
//   write ends the episode. The watchdog runs from the first write after activate.
// - re-engagement: after any interruption of the force path (activation, a watchdog
//   episode, a failed read of the device: each read that fails sends zero), the commands are
//   scaled from zero at the first write after it up to one reengage_s later, so the force
//   comes back gently.
// - slew limit, the last line: between two forces sent to the inner device, the force
//   changes by at most the profile's max_force_step_n_per_ms times the time between them,
//   counted as at most a millisecond (so a 5 kHz loop moves 2 N per tick at 10 N/ms; a write
//   after a silence moves one millisecond's worth). Counted. Only deactivate() zeroes at once.
// - deactivate(): writes zero to the inner device (at the latest time seen, 0 if none), then
//   deactivates it.
// The fault bits in a sample are the inner device's plus the wrapper's for the force acting
// now: clamped / nonfinite_command for the last command, watchdog during an episode.
#include <cstdint>
#include <memory>

#include "core/devices/device.h"

namespace enact::devices {

struct SafetyParams {
  double watchdog_s = 0.010;  // > 0: longest time without a command before the force ramps down
  double ramp_s = 0.005;      // >= 0: time of the ramp from the last command to zero
  double reengage_s = 0.100;  // >= 0: time of the ramp from zero back to the commands after an interruption
};

class SafeForceDevice final : public ForceDevice {
 public:
  SafeForceDevice(std::unique_ptr<ForceDevice> inner, SafetyParams params = {});

  // validate the params, configure the inner device; throws config::Error
  void configure() override;
  // activate the inner device; counters are kept, the watchdog waits for the first write
  void activate() override;
  // the inner device's sample, with the watchdog run at now_ns, the wrapper's fault bits and
  // the force it sends to the inner device now (force_n)
  bool read(std::int64_t now_ns, ForceSample& out) noexcept override;
  // the command made safe (finite, within the peak force), sent on to the inner device
  void write(std::int64_t now_ns, const math::Vec3& force_n) noexcept override;
  // zero force to the inner device, then deactivate it
  void deactivate() noexcept override;
  const devices::DeviceProfile& profile() const override { return inner_->profile(); }
  HandSource* simulated_hand() noexcept override { return inner_->simulated_hand(); }

  // commands scaled down to the peak force, since construction
  std::uint64_t clamps() const { return clamps_; }
  // NaN/Inf commands replaced by zero, since construction
  std::uint64_t nonfinite() const { return nonfinite_; }
  // watchdog episodes, since construction
  std::uint64_t watchdog_trips() const { return watchdog_trips_; }
  // forces held back by the slew limit, since construction
  std::uint64_t slew_limited() const { return slew_limited_; }
  // re-engagements begun (a ramp from zero after an interruption), since construction
  std::uint64_t reengagements() const { return reengagements_; }
  // the fault bits of the last sample, updated by writes since (0: all well)
  std::uint32_t faults() const { return faults_; }
  bool faulted() const { return faults_ != 0; }
  // the force last sent to the inner device
  math::Vec3 sent_force_n() const { return sent_n_; }
  ForceDevice& inner() { return *inner_; }

 private:
  void send(std::int64_t now_ns, const math::Vec3& force_n) noexcept;
  void see(std::int64_t now_ns) noexcept;
  double engagement(std::int64_t now_ns) noexcept;
  math::Vec3 slew_limit(std::int64_t now_ns, const math::Vec3& force_n) noexcept;

  std::unique_ptr<ForceDevice> inner_;
  SafetyParams params_;
  std::int64_t watchdog_ns_ = 0;
  std::int64_t ramp_ns_ = 0;
  std::int64_t reengage_ns_ = 0;
  double step_n_per_ns_ = 0.0;
  // the last command, made safe, and when it arrived
  math::Vec3 command_n_;
  std::uint32_t command_faults_ = 0;
  bool commanded_ = false;
  std::int64_t command_ns_ = 0;
  bool in_episode_ = false;
  math::Vec3 trip_n_;           // the force sent when the episode began
  bool interrupted_ = true;        // the next write begins a re-engagement
  std::int64_t engage_ns_ = 0;     // when the current re-engagement began
  math::Vec3 sent_n_;
  std::int64_t sent_ns_ = 0;
  bool sent_any_ = false;          // since activate
  std::uint32_t faults_ = 0;
  std::int64_t latest_ns_ = 0;  // the latest time seen
  bool seen_ = false;
  std::uint64_t clamps_ = 0;
  std::uint64_t nonfinite_ = 0;
  std::uint64_t watchdog_trips_ = 0;
  std::uint64_t slew_limited_ = 0;
  std::uint64_t reengagements_ = 0;
};

}  // namespace enact::devices
