#include "core/devices/falcon/protocol.h"

#include <algorithm>
#include <cstring>

namespace enact::devices::falcon {
namespace {

// three int16 as 12 nibble bytes from byte 1, least significant nibble first
void put_words(const std::array<std::int16_t, 3>& words, Packet& p) {
  for (int w = 0; w < 3; ++w) {
    const auto v = static_cast<std::uint16_t>(words[static_cast<std::size_t>(w)]);
    for (int n = 0; n < 4; ++n) p[static_cast<std::size_t>(1 + 4 * w + n)] = static_cast<std::uint8_t>(kOffset + ((v >> (4 * n)) & 0xF));
  }
}

bool nibble(std::uint8_t byte) { return byte >= kOffset && byte <= kOffset + 0xF; }

bool get_words(const Packet& p, std::array<std::int16_t, 3>& words) {
  for (int w = 0; w < 3; ++w) {
    std::uint16_t v = 0;
    for (int n = 0; n < 4; ++n) {
      const std::uint8_t b = p[static_cast<std::size_t>(1 + 4 * w + n)];
      if (!nibble(b)) return false;
      v = static_cast<std::uint16_t>(v | ((b - kOffset) << (4 * n)));
    }
    words[static_cast<std::size_t>(w)] = static_cast<std::int16_t>(v);
  }
  return true;
}

Packet framed() {
  Packet p{};
  p[0] = kStart;
  p[14] = kOffset;
  p[15] = kEnd;
  return p;
}

bool frame_ok(const Packet& p) { return p[0] == kStart && p[15] == kEnd && nibble(p[14]); }

}  // namespace

Packet encode(const Command& command) {
  Packet p = framed();
  put_words(command.motor, p);
  p[13] = static_cast<std::uint8_t>(kOffset + ((command.leds & (kLedGreen | kLedBlue | kLedRed)) | (command.homing ? kHomingMode : 0)));
  return p;
}

bool decode(const Packet& packet, Reading& out) {
  if (!frame_ok(packet) || packet[13] < kOffset || packet[13] > kOffset + 0x7F) return false;
  if (!get_words(packet, out.encoder)) return false;
  const int info = packet[13] - kOffset;
  out.homed = static_cast<std::uint8_t>((info >> 4) & kAllHomed);
  out.buttons = static_cast<std::uint8_t>(info & 0x0F);
  return true;
}

Packet encode(const Reading& reading) {
  Packet p = framed();
  put_words(reading.encoder, p);
  p[13] = static_cast<std::uint8_t>(kOffset + (((reading.homed & kAllHomed) << 4) | (reading.buttons & 0x0F)));
  return p;
}

bool decode(const Packet& packet, Command& out) {
  if (!frame_ok(packet) || !nibble(packet[13])) return false;
  if (!get_words(packet, out.motor)) return false;
  const int info = packet[13] - kOffset;
  out.leds = static_cast<std::uint8_t>(info & (kLedGreen | kLedBlue | kLedRed));
  out.homing = (info & kHomingMode) != 0;
  return true;
}

void PacketReader::feed(const std::uint8_t* data, int n) noexcept {
  const int room = static_cast<int>(buf_.size()) - size_;
  const int take = std::min(n, room);
  if (take > 0) std::memcpy(buf_.data() + size_, data, static_cast<std::size_t>(take));
  size_ += std::max(take, 0);
  dropped_ += static_cast<std::uint64_t>(n - std::max(take, 0));
}

bool PacketReader::next(Packet& out) noexcept {
  int start = 0;
  bool found = false;
  while (start < size_) {
    // skip to the next start marker
    while (start < size_ && buf_[static_cast<std::size_t>(start)] != kStart) ++start;
    if (size_ - start < kPacketSize) break;  // wait for the rest
    if (buf_[static_cast<std::size_t>(start + kPacketSize - 1)] == kEnd) {
      std::memcpy(out.data(), buf_.data() + start, kPacketSize);
      start += kPacketSize;
      found = true;
      break;
    }
    ++start;  // not a packet: drop this marker
  }
  // keep what follows
  std::memmove(buf_.data(), buf_.data() + start, static_cast<std::size_t>(size_ - start));
  size_ -= start;
  return found;
}

}  // namespace enact::devices::falcon
