#include "core/devices/falcon/link.h"

#include <algorithm>
#include <cstring>

#include "core/rt/clock.h"

namespace enact::devices::falcon {
namespace {

constexpr int kControlTimeout_ms = 1000;
constexpr std::int64_t kHandshakeTimeout_ns = 100'000'000;  // an answer to the check message
constexpr std::int64_t kEchoTimeout_ns = 1'000'000'000;     // a chunk's echo

std::string hex(const std::uint8_t* data, int n) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (int i = 0; i < n; ++i) {
    out += (i ? " " : "");
    out += digits[data[i] >> 4];
    out += digits[data[i] & 0xF];
  }
  return out;
}

}  // namespace

usb::Outcome Link::ftdi(std::uint8_t request, std::uint16_t value) noexcept {
  const usb::Outcome o = t_.control({usb::kVendorOut, request, value, 0}, nullptr, 0, kControlTimeout_ms);
  if (!o.ok()) last_error_ = o.status;
  return o;
}

bool Link::setup(std::initializer_list<std::pair<std::uint8_t, std::uint16_t>> requests, std::string& why) {
  for (const auto& [request, value] : requests) {
    if (const usb::Outcome o = ftdi(request, value); !o.ok()) {
      why = "FT232 request " + std::to_string(request) + " (value " + std::to_string(value) + "): " + usb::to_string(o.status);
      return false;
    }
  }
  return true;
}

usb::Outcome Link::read_data(std::uint8_t* data, int max, int timeout_ms) noexcept {
  std::uint8_t buf[kReadSize];
  usb::Outcome o = t_.bulk(kEndpointIn, buf, kReadSize, std::max(timeout_ms, 1));
  if (!o.ok() && o.status != usb::Status::timeout) last_error_ = o.status;
  // every read starts with the FT232's two status bytes
  const int n = std::clamp(o.bytes - kStatusBytes, 0, max);
  if (n > 0) std::memcpy(data, buf + kStatusBytes, static_cast<std::size_t>(n));
  o.bytes = n;
  return o;
}

int Link::read_exactly(std::uint8_t* data, int count, std::int64_t timeout_ns) noexcept {
  const std::int64_t deadline = rt::now_ns() + timeout_ns;
  int got = 0;
  while (got < count) {
    const std::int64_t left_ns = deadline - rt::now_ns();
    if (left_ns <= 0) break;
    const usb::Outcome o = read_data(data + got, count - got, static_cast<int>((left_ns + 999'999) / 1'000'000));
    got += o.bytes;
    if (o.status == usb::Status::no_device || o.status == usb::Status::io || o.status == usb::Status::stall) break;
  }
  return got;
}

bool Link::write_all(const std::uint8_t* data, int length, std::string* why, int timeout_ms) noexcept {
  const usb::Outcome o = t_.bulk(kEndpointOut, const_cast<std::uint8_t*>(data), length, timeout_ms);
  if (o.ok() && o.bytes == length) return true;
  last_error_ = o.ok() ? usb::Status::io : o.status;
  if (why) *why = "bulk write of " + std::to_string(length) + " bytes: " + usb::to_string(last_error_);
  return false;
}

bool Link::enter_boot_loader(int tries, std::string& why) {
  // firmware mode: purge, latency 16 ms, 9600 8N1, no flow control, RTS low, DTR low then
  // high (the DSP resets into its boot loader)
  if (!setup({{ftdi::kReset, ftdi::kPurgeRx},
              {ftdi::kReset, ftdi::kPurgeTx},
              {ftdi::kLatencyTimer, ftdi::kLatencyBoot_ms},
              {ftdi::kBaudRate, ftdi::kBaud9600},
              {ftdi::kLineSettings, ftdi::k8N1},
              {ftdi::kFlowControl, ftdi::kNoFlowControl},
              {ftdi::kModemControl, ftdi::kRtsLow},
              {ftdi::kModemControl, ftdi::kDtrLow},
              {ftdi::kModemControl, ftdi::kDtrHigh}},
             why)) {
    return false;
  }
  reader_.clear();
  // the check message, until answered right
  std::uint8_t answer[kCheckReply.size()];
  int tried = 0;
  bool checked = false;
  while (!checked && tried < tries) {
    ++tried;
    if (!write_all(kCheckRequest.data(), static_cast<int>(kCheckRequest.size()), &why)) return false;
    const int got = read_exactly(answer, static_cast<int>(kCheckReply.size()), kHandshakeTimeout_ns);
    if (last_error_ == usb::Status::no_device) {
      why = "the device was unplugged";
      return false;
    }
    checked = got == static_cast<int>(kCheckReply.size()) && std::equal(kCheckReply.begin(), kCheckReply.end(), answer);
    if (!checked) why = "the boot loader answered the check message " + std::to_string(tried) + " times wrongly (last: " + hex(answer, got) + ")";
  }
  if (!checked) return false;
  // DTR low, the upload's baud rate, the boot byte echoed
  if (!setup({{ftdi::kModemControl, ftdi::kDtrLow}, {ftdi::kBaudRate, ftdi::kBaudBoot}}, why)) return false;
  if (!write_all(&kBootByte, 1, &why)) return false;
  std::uint8_t echo = 0;
  if (read_exactly(&echo, 1, kHandshakeTimeout_ns) != 1 || echo != kBootByte) {
    why = "the boot loader did not echo the boot byte";
    return false;
  }
  return true;
}

bool Link::upload(const std::vector<std::uint8_t>& firmware, std::string& why) {
  std::uint8_t echo[kFirmwareChunk];
  for (std::size_t at = 0; at < firmware.size(); at += kFirmwareChunk) {
    const int n = static_cast<int>(std::min<std::size_t>(kFirmwareChunk, firmware.size() - at));
    if (!write_all(firmware.data() + at, n, &why)) return false;
    const int got = read_exactly(echo, n, kEchoTimeout_ns);
    if (got != n || !std::equal(echo, echo + n, firmware.begin() + static_cast<std::ptrdiff_t>(at))) {
      why = "the firmware chunk at byte " + std::to_string(at) + " was not echoed back (" + std::to_string(got) + " of " + std::to_string(n) + " bytes" +
            (got == n ? ", different" : "") + ")";
      return false;
    }
  }
  return true;
}

bool Link::enter_normal_mode(std::string& why) {
  reader_.clear();
  return setup({{ftdi::kLatencyTimer, ftdi::kLatencyRun_ms}, {ftdi::kBaudRate, ftdi::kBaudRun}, {ftdi::kReset, ftdi::kPurgeRx}, {ftdi::kReset, ftdi::kPurgeTx}},
               why);
}

usb::Status Link::send(const Command& command, int timeout_ms) noexcept {
  const Packet p = encode(command);
  return write_all(p.data(), kPacketSize, nullptr, timeout_ms) ? usb::Status::ok : last_error_;
}

usb::Status Link::exchange(const Command& command, Reading& out, std::int64_t timeout_ns) noexcept {
  const std::int64_t deadline = rt::now_ns() + timeout_ns;
  if (const usb::Status s = send(command, static_cast<int>((timeout_ns + 999'999) / 1'000'000)); s != usb::Status::ok) return s;
  std::uint8_t data[kReadSize];
  Packet packet;
  bool answered = false;
  while (!answered) {
    const std::int64_t left_ns = deadline - rt::now_ns();
    if (left_ns <= 0) return usb::Status::timeout;
    const usb::Outcome o = read_data(data, kReadSize, static_cast<int>((left_ns + 999'999) / 1'000'000));
    if (o.status == usb::Status::no_device || o.status == usb::Status::io || o.status == usb::Status::stall) return o.status;
    reader_.feed(data, o.bytes);
    // the newest whole packet that decodes
    while (reader_.next(packet)) {
      Reading r;
      if (decode(packet, r)) {
        out = r;
        answered = true;
      } else {
        ++bad_answers_;
      }
    }
  }
  return usb::Status::ok;
}

}  // namespace enact::devices::falcon
