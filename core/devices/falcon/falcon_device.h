#pragma once
// The Novint Falcon as a ForceDevice (`device: falcon`), over any USB bus: the real one
// (usb/libusb.h) or a fake one with the emulator (emulator.h).
//
// configure(): find and open the Falcon (config::Error with the fix when it is absent, not
// accessible, busy); if its firmware is not running, upload the user's firmware file
// (`firmware`; enact never ships it) with retries, as real Falcons often fail the first
// handshakes; home it (the LED is red until the user has moved the grip all the way out and
// pushed it straight all the way in; then green); then start the I/O thread, which
// exchanges lock-step packets at about 1 kHz from then on, with zero force until activate.
//
// Each exchange: the latest force command (clamped to max_force_n; zero when inactive, and
// when write() has not been called for kCommandTimeout_s: the loop stalled) becomes motor
// commands through the transposed Jacobian at the last measured position; the answer's
// encoder counts become the position through the forward kinematics, and a velocity
// estimate; the sample is handed to the real-time side without locks.
//
// read() and write() are the real-time side: no allocation, no lock, no blocking. read()
// reports device_error when the device is unplugged (a transfer answered no_device) or its
// newest sample is older than stale_s (the device stopped answering): within stale_s plus
// one read, under the 10 ms the safety layer allows. deactivate() zeroes the force and
// waits (at most 200 ms) for a zero packet to have gone out. The destructor stops the
// thread, sends a last zero packet with the LEDs off, and closes the device. A fatal signal
// in the process sends a zero packet from the signal handler (usb/emergency.h).
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "core/devices/device.h"
#include "core/devices/falcon/kinematics.h"
#include "core/devices/io_exchange.h"
#include "core/devices/falcon/link.h"
#include "core/devices/usb/emergency.h"
#include "core/devices/usb/io_thread.h"
#include "core/devices/usb/transport.h"

namespace enact::devices::falcon {

struct FalconParams {
  std::string serial;              // empty: the first Falcon found
  std::string firmware;            // the firmware file to upload when none runs (empty: it must run already)
  int firmware_attempts = 5;       // >= 1: whole firmware loads before giving up
  int handshake_tries = 20;        // >= 1: check messages per load
  double homing_timeout_s = 60.0;  // > 0: how long the user has to home the grip
  double max_force_n = 8.0;        // (0, 9]: the force is clamped to this (the Falcon is rated about 9 N)
  double stale_s = 0.005;          // (0, 0.009]: a sample older than this is a device error
  double io_period_s = 0.001;      // (0, 0.01]: the lock-step exchange period
};

class FalconForceDevice final : public ForceDevice {
 public:
  FalconForceDevice(FalconParams params, std::unique_ptr<usb::Bus> bus);
  ~FalconForceDevice() override;
  FalconForceDevice(const FalconForceDevice&) = delete;
  FalconForceDevice& operator=(const FalconForceDevice&) = delete;

  // validate, open, load the firmware if needed, home, start the I/O thread; throws config::Error
  void configure() override;
  // commands reach the motors from now on
  void activate() override;
  bool read(std::int64_t now_ns, ForceSample& out) noexcept override;
  void write(std::int64_t now_ns, const math::Vec3& force_n) noexcept override;
  void deactivate() noexcept override;
  // the "falcon" profile, peak force = max_force_n
  const devices::DeviceProfile& profile() const override { return profile_; }

  // since configure: exchanges answered, exchanges without an answer in time
  std::uint64_t exchanges() const { return exchanges_.load(); }
  std::uint64_t missed() const { return missed_.load(); }
  // the device answered no_device (unplugged)
  bool unplugged() const { return exchange_.failed(); }
  // whether configure() uploaded the firmware (false: it was running)
  bool uploaded_firmware() const { return uploaded_; }

  // how long write() may stay silent before the I/O thread zeroes the force on its own
  static constexpr double kCommandTimeout_s = 0.020;

 private:
  void validate() const;
  void load_firmware(Link& link);
  bool probe(Link& link);
  void home(Link& link);
  bool io_step(std::int64_t now_ns) noexcept;
  bool take(const Reading& r, std::int64_t now_ns) noexcept;
  Command command(std::int64_t now_ns) noexcept;
  static void emergency(void* self) noexcept;

  FalconParams params_;
  std::unique_ptr<usb::Bus> bus_;
  devices::DeviceProfile profile_;
  std::unique_ptr<usb::Transport> transport_;
  std::unique_ptr<Link> link_;
  usb::EmergencyStop emergency_;
  usb::IoThread io_;
  Packet zero_packet_{};  // zero force, LEDs off: the last words
  std::int64_t stale_ns_ = 0;
  bool configured_ = false;
  bool uploaded_ = false;
  // real-time side <-> I/O thread (unplugged: the exchange's failure)
  IoExchange exchange_;
  std::atomic<bool> halted_{false};        // the emergency stop ran: no more packets
  std::atomic<std::uint64_t> exchanges_{0};
  std::atomic<std::uint64_t> missed_{0};
  // the I/O thread's own state
  Vec3 device_position_m_{0.0, 0.0, kCentreZ_m};  // the last position (device frame): the FK's warm start
  Jacobian jacobian_{};
  Vec3 velocity_m_per_s_;
  std::int64_t last_ns_ = 0;
};

}  // namespace enact::devices::falcon
