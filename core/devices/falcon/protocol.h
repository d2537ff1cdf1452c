#pragma once
// The Novint Falcon's wire protocol, from public descriptions: libnifalcon (Kyle Machulis et
// al., BSD; src/comm/FalconCommLibUSB.cpp, src/core/FalconFirmware.cpp,
// src/firmware/FalconFirmwareNovintSDK.cpp and its header's protocol notes). Our own code.
//
// USB: 0403:cb48, an FTDI FT232 serial bridge; interface 0, bulk OUT 0x02, bulk IN 0x81. The
// FT232 is driven by vendor control requests (reset/purge, modem control, flow control,
// baud rate, line settings, latency timer), and puts two status bytes (modem and line
// status) at the start of every bulk IN read.
//
// Start-up: the firmware is uploaded by the host at every power-up (the user supplies the
// file; enact never ships it): firmware mode (purge, latency timer 16 ms, 9600 baud, 8N1, no
// flow control, RTS low, DTR low then high: the DSP resets into its boot loader), a check
// message 0A 43 0D answered 0A 44 2C 0D (retried: the first ones often fail), DTR low and a
// faster baud rate (divisor 0x15), the byte 'A' echoed, then the firmware in 62-byte
// chunks, each echoed back byte for byte; then normal mode (latency timer 1 ms, baud
// divisor 0x0002, purge).
//
// Running: strictly lock-step 16-byte packets, about 1 kHz: each packet to the device is
// answered by one packet from it. Both are printable: '<', 14 payload bytes, '>'.
//   host -> device: bytes 1..12: three int16 motor commands, each as 4 nibbles, least
//     significant first, each nibble + 0x41; byte 13: 0x41 + (LEDs | homing mode bit);
//     byte 14: 0x41.
//   device -> host: bytes 1..12: three int16 encoder counts, coded the same way; byte 13:
//     0x41 + (homed axes << 4 | grip buttons); byte 14: 0x41.
#include <array>
#include <cstdint>

namespace enact::devices::falcon {

// USB
constexpr std::uint8_t kEndpointOut = 0x02;
constexpr std::uint8_t kEndpointIn = 0x81;
constexpr int kInterface = 0;
constexpr int kStatusBytes = 2;  // at the start of every read
constexpr int kReadSize = 64;    // a full-speed bulk packet: 2 status + 62 data bytes

// FT232 vendor requests (bRequest) and their values (wValue)
namespace ftdi {
constexpr std::uint8_t kReset = 0;
constexpr std::uint8_t kModemControl = 1;
constexpr std::uint8_t kFlowControl = 2;
constexpr std::uint8_t kBaudRate = 3;
constexpr std::uint8_t kLineSettings = 4;
constexpr std::uint8_t kLatencyTimer = 9;
constexpr std::uint16_t kPurgeRx = 1;
constexpr std::uint16_t kPurgeTx = 2;
constexpr std::uint16_t kDtrLow = 0x0100;   // mask bit 8: DTR, value bit 0
constexpr std::uint16_t kDtrHigh = 0x0101;
constexpr std::uint16_t kRtsLow = 0x0200;   // mask bit 9: RTS, value bit 1
constexpr std::uint16_t kNoFlowControl = 0;
constexpr std::uint16_t k8N1 = 0x0008;      // 8 data bits, no parity, 1 stop bit
constexpr std::uint16_t kBaud9600 = 0x4138;  // the FT232's divisor code for 9600 baud
constexpr std::uint16_t kBaudBoot = 0x0015;  // divisor 21: about 140 kbaud, firmware upload
constexpr std::uint16_t kBaudRun = 0x0002;   // divisor 2: the running firmware's rate
constexpr std::uint16_t kLatencyBoot_ms = 16;
constexpr std::uint16_t kLatencyRun_ms = 1;
}  // namespace ftdi

// the boot loader's handshake
constexpr std::array<std::uint8_t, 3> kCheckRequest = {0x0A, 0x43, 0x0D};
constexpr std::array<std::uint8_t, 4> kCheckReply = {0x0A, 0x44, 0x2C, 0x0D};
constexpr std::uint8_t kBootByte = 0x41;  // 'A', echoed
constexpr int kFirmwareChunk = 62;

// the running firmware's packets
constexpr int kPacketSize = 16;
using Packet = std::array<std::uint8_t, kPacketSize>;
constexpr std::uint8_t kStart = 0x3C;   // '<'
constexpr std::uint8_t kEnd = 0x3E;     // '>'
constexpr std::uint8_t kOffset = 0x41;  // 'A': added to every payload byte

// byte 13 host -> device
constexpr std::uint8_t kHomingMode = 0x01;
constexpr std::uint8_t kLedGreen = 0x02;
constexpr std::uint8_t kLedBlue = 0x04;
constexpr std::uint8_t kLedRed = 0x08;
// byte 13 device -> host: homed axes (bits 0..2 after the shift) and grip buttons
constexpr std::uint8_t kAllHomed = 0x07;

// what the host sends
struct Command {
  std::array<std::int16_t, 3> motor{};  // motor commands (libnifalcon: -10000 per N m of joint torque)
  std::uint8_t leds = 0;                // kLed* bits
  bool homing = false;                  // homing mode on
  bool operator==(const Command&) const = default;
};

// what the device answers
struct Reading {
  std::array<std::int16_t, 3> encoder{};  // encoder counts, one per arm
  std::uint8_t homed = 0;                 // bit i: arm i homed
  std::uint8_t buttons = 0;               // bit i: grip button i pressed
  bool operator==(const Reading&) const = default;
};

// host side
Packet encode(const Command& command);
bool decode(const Packet& packet, Reading& out);  // false: not a valid answer
// device side (the emulator)
Packet encode(const Reading& reading);
bool decode(const Packet& packet, Command& out);  // false: not a valid command

// Bytes from the device (status bytes already removed) into packets, like libnifalcon's
// parser: skip to '<', take 16 bytes, keep them when the 16th is '>', else drop that '<'
// and look again. Fixed buffer; allocates nothing.
class PacketReader {
 public:
  // append n bytes (what does not fit is dropped, counted in dropped())
  void feed(const std::uint8_t* data, int n) noexcept;
  // the next whole packet, if any
  bool next(Packet& out) noexcept;
  void clear() noexcept { size_ = 0; }
  int pending() const { return size_; }
  std::uint64_t dropped() const { return dropped_; }

 private:
  std::array<std::uint8_t, 256> buf_{};
  int size_ = 0;
  std::uint64_t dropped_ = 0;
};

}  // namespace enact::devices::falcon
