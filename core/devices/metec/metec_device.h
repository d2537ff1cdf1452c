#pragma once
// Metec Braille cells as a TactileDevice (`device: metec`), over any USB bus: the real one
// (usb/libusb.h) or a fake one with the emulator (emulator.h). The pin array sits on
// adjacent cells from first_cell (protocol.h: the mapping).
//
// configure(): find and open the display (config::Error with the fix when it is absent, not
// accessible, or held by BRLTTY), read its identity and status, check the pins fit on its
// cells; then start the I/O thread. The high voltage stays off until activate.
// activate(): the I/O thread writes every module the pins use with all pins down, then
// switches the high voltage on. From then on, each period it writes the modules whose cells
// changed, and only those (one control transfer per module), and polls the status now and
// then to notice a display that stopped answering.
// deactivate(), the destructor, and any fault (a transfer that fails, times out, or finds
// the display unplugged): pins lowered and the high voltage off. A fatal signal in the
// process switches the high voltage off from the signal handler (usb/emergency.h).
//
// write() and shown() are the real-time side: no allocation, no lock, no blocking. shown()
// says what the cells physically show: the display does not report its pins, so it is the
// cells' motion (PinMotion, rise_time_s) from the time each write was taken by the display
// (the transfer's completion), all pins falling from the time the high voltage went off.
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "core/devices/device.h"
#include "core/devices/metec/protocol.h"
#include "core/devices/usb/emergency.h"
#include "core/devices/usb/io_thread.h"
#include "core/devices/usb/latest.h"
#include "core/devices/usb/transport.h"
#include "core/rt/clock.h"

namespace enact::devices::metec {

struct MetecParams {
  std::string serial;          // empty: the first display found
  int rows = 4;                // 1 .. 4
  int cols = 4;                // 1 .. 8, rows * cols <= 32
  int first_cell = 0;          // the cell under pin columns 0 and 1
  double rise_time_s = 0.024;  // > 0: the cells' full stroke (Metec: 24 ms)
  double io_period_s = 0.001;  // (0, 0.05]: how often changed pins are written
  double status_period_s = 0.05;  // (0, 1]: how often the status is polled
  int timeout_ms = 20;         // 1 .. 1000: a control transfer's timeout (a display that stops answering)
  rt::ClockFn clock = nullptr;  // stamps the cells' motion (monotonic ns); null: CLOCK_MONOTONIC
};

class MetecTactileDevice final : public TactileDevice {
 public:
  MetecTactileDevice(MetecParams params, std::unique_ptr<usb::Bus> bus);
  ~MetecTactileDevice() override;
  MetecTactileDevice(const MetecTactileDevice&) = delete;
  MetecTactileDevice& operator=(const MetecTactileDevice&) = delete;

  void configure() override;
  // pins down, then high voltage on (done by the I/O thread; waits at most 200 ms for it)
  void activate() override;
  void write(std::int64_t now_ns, std::uint32_t pins) noexcept override;
  void shown(std::int64_t now_ns, float* levels, int count) noexcept override;
  bool motion(PinMotion& out) const noexcept override;
  int rows() const override { return params_.rows; }
  int cols() const override { return params_.cols; }
  // pins lowered, high voltage off (waits at most 200 ms for the I/O thread)
  void deactivate() noexcept override;

  // a fault lowered the pins and switched the high voltage off (the device must be configured again)
  bool faulted() const { return faulted_.load(); }
  bool unplugged() const { return unplugged_.load(); }
  // the display's identity text and its number of cells (after configure)
  const std::string& identity() const { return identity_; }
  int display_cells() const { return display_cells_; }
  // module writes made since configure
  std::uint64_t module_writes() const { return module_writes_.load(); }

 private:
  void validate() const;
  bool io_step(std::int64_t now_ns) noexcept;
  bool write_modules(std::uint32_t pins, bool all) noexcept;
  bool set_high_voltage(bool on) noexcept;
  void fault(usb::Status status) noexcept;
  static void emergency(void* self) noexcept;
  std::int64_t now() const noexcept;

  MetecParams params_;
  std::unique_ptr<usb::Bus> bus_;
  Layout layout_;
  std::unique_ptr<usb::Transport> transport_;
  usb::EmergencyStop emergency_;
  usb::IoThread io_;
  std::string identity_;
  int display_cells_ = 0;
  std::uint32_t mask_ = 0;
  bool configured_ = false;
  // real-time side <-> I/O thread
  usb::Latest<PinMotion> motion_;
  std::atomic<std::uint32_t> target_{0};
  std::atomic<bool> active_{false};
  std::atomic<bool> faulted_{false};
  std::atomic<bool> unplugged_{false};
  std::atomic<bool> halted_{false};
  std::atomic<std::uint64_t> switched_on_{0};   // high voltage switched on after activate
  std::atomic<std::uint64_t> switched_off_{0};  // pins lowered and high voltage off after deactivate
  std::atomic<std::uint64_t> module_writes_{0};
  // the I/O thread's own state
  PinMotion shown_;  // what the cells show, published in motion_
  bool high_voltage_ = false;
  std::array<std::array<std::uint8_t, kCellsPerModule>, kMaxModules> written_{};
  std::int64_t next_status_ns_ = 0;
};

}  // namespace enact::devices::metec
