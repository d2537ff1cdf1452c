#pragma once
// The Falcon's protocol steps over a USB transport, synchronous: the FT232's modes, the boot
// loader's handshake, the firmware upload, and one lock-step packet exchange (protocol.h
// says what goes over the wire and where each fact comes from). Used by the backend's
// configure() and by its I/O thread, one thread at a time. exchange() allocates nothing.
#include <cstdint>
#include <string>
#include <vector>

#include "core/devices/falcon/protocol.h"
#include "core/devices/usb/transport.h"

namespace enact::devices::falcon {

class Link {
 public:
  static constexpr int kWriteTimeout_ms = 1000;  // start-up writes

  explicit Link(usb::Transport& transport) : t_(transport) {}

  // one FT232 vendor request (host to device, no data)
  usb::Outcome ftdi(std::uint8_t request, std::uint16_t value) noexcept;
  // firmware mode, the DSP reset into its boot loader, then the check message until it is
  // answered right (at most `tries` times), the boot byte echoed; false with the reason
  bool enter_boot_loader(int tries, std::string& why);
  // the firmware in 62-byte chunks, each echoed back byte for byte; false with the reason
  bool upload(const std::vector<std::uint8_t>& firmware, std::string& why);
  // the running firmware's serial settings; false with the reason
  bool enter_normal_mode(std::string& why);
  // one lock-step exchange: `command` out, its answer in within timeout_ns (the newest
  // whole packet received: a late answer to an earlier command is superseded)
  usb::Status exchange(const Command& command, Reading& out, std::int64_t timeout_ns) noexcept;
  // a packet out within timeout_ms, no answer awaited
  usb::Status send(const Command& command, int timeout_ms) noexcept;

  // the last transfer status that was not ok (for messages)
  usb::Status last_error() const { return last_error_; }
  // answers that were not valid packets, since construction
  std::uint64_t bad_answers() const { return bad_answers_; }

 private:
  // data bytes (status bytes removed) read within timeout_ms into `data`
  usb::Outcome read_data(std::uint8_t* data, int max, int timeout_ms) noexcept;
  // read until `count` data bytes arrived or timeout_ns passed; the bytes into `data`
  int read_exactly(std::uint8_t* data, int count, std::int64_t timeout_ns) noexcept;
  bool write_all(const std::uint8_t* data, int length, std::string* why, int timeout_ms = kWriteTimeout_ms) noexcept;
  bool setup(std::initializer_list<std::pair<std::uint8_t, std::uint16_t>> requests, std::string& why);

  usb::Transport& t_;
  PacketReader reader_;
  usb::Status last_error_ = usb::Status::ok;
  std::uint64_t bad_answers_ = 0;
};

}  // namespace enact::devices::falcon
