// The Falcon's packets against byte sequences written by hand from the public descriptions
// (libnifalcon's FalconFirmwareNovintSDK.h notes: '<', 14 payload bytes of a nibble + 0x41,
// '>'; motor words least significant nibble first; the info byte), and the packet reader.
#include "core/devices/falcon/protocol.h"

#include <gtest/gtest.h>

#include <string>

namespace enact::devices::falcon {
namespace {

Packet bytes(const std::string& text) {
  EXPECT_EQ(text.size(), 16u) << text;
  Packet p{};
  for (std::size_t i = 0; i < p.size() && i < text.size(); ++i) p[i] = static_cast<std::uint8_t>(text[i]);
  return p;
}

std::string text(const Packet& p) { return std::string(p.begin(), p.end()); }

TEST(FalconProtocol, ANullCommandIsTheNullStringOfTheDescription) {
  // "A null input/output string looks like: <AAAAAAAAAAAAAA>"
  EXPECT_EQ(text(encode(Command{})), "<AAAAAAAAAAAAAA>");
}

TEST(FalconProtocol, MotorWordsAreNibblesLeastSignificantFirst) {
  // 1 -> 1,0,0,0 -> "BAAA"; -1 = 0xFFFF -> "PPPP"; 0x1234 -> 4,3,2,1 -> "EDCB";
  // info: red LED 0x08 | homing 0x01 = 0x09 -> 'J'; byte 14 'A'
  Command c;
  c.motor = {1, -1, 0x1234};
  c.leds = kLedRed;
  c.homing = true;
  EXPECT_EQ(text(encode(c)), "<BAAAPPPPEDCBJA>");
  // green and blue LEDs without homing: 0x02 | 0x04 = 0x06 -> 'G'
  Command g;
  g.leds = kLedGreen | kLedBlue;
  EXPECT_EQ(text(encode(g)), "<AAAAAAAAAAAAGA>");
}

TEST(FalconProtocol, TheDescriptionsEncoderExampleDecodes) {
  // the worked example: 0x4A 0x46 0x4B 0x50 -> nibbles 9, 5, A, F -> 0xFA59 -> as int16 -1447
  Packet p = bytes("<JFKPAAAAAAAAAA>");
  Reading r;
  ASSERT_TRUE(decode(p, r));
  EXPECT_EQ(r.encoder[0], -1447);
  EXPECT_EQ(r.encoder[1], 0);
  EXPECT_EQ(r.encoder[2], 0);
}

TEST(FalconProtocol, TheInfoByteCarriesHomedAxesAndButtons) {
  // info 0x41 + (homed 0b101 << 4 | buttons 0b0110) = 0x41 + 0x56 = 0x97
  Packet p = bytes("<BAAAPPPPEDCB?A>");
  p[13] = 0x97;
  Reading r;
  ASSERT_TRUE(decode(p, r));
  EXPECT_EQ(r.encoder[0], 1);
  EXPECT_EQ(r.encoder[1], -1);
  EXPECT_EQ(r.encoder[2], 0x1234);
  EXPECT_EQ(r.homed, 0b101);
  EXPECT_EQ(r.buttons, 0b0110);
  // and the device side writes the same bytes
  EXPECT_EQ(encode(r), p);
}

TEST(FalconProtocol, MalformedPacketsAreRefused) {
  Reading r;
  EXPECT_FALSE(decode(bytes("<AAAAAAAAAAAAAA<"), r)) << "no end marker";
  EXPECT_FALSE(decode(bytes("xAAAAAAAAAAAAAA>"), r)) << "no start marker";
  EXPECT_FALSE(decode(bytes("<AAAAQAAAAAAAAA>"), r)) << "'Q' is not a nibble + 0x41";
  EXPECT_FALSE(decode(bytes("<AAAAAAAAAAAA@A>"), r)) << "info byte below 0x41";
  Command c;
  EXPECT_FALSE(decode(bytes("<AAAAAAAAAAAAQA>"), c)) << "a command's info byte is a nibble";
}

TEST(FalconProtocol, CommandsRoundTripThroughTheDeviceSide) {
  for (int v : {0, 1, -1, 4096, -4096, 32767, -32768, 12345}) {
    Command c;
    c.motor = {static_cast<std::int16_t>(v), static_cast<std::int16_t>(-v / 2), static_cast<std::int16_t>(v / 3)};
    c.leds = kLedBlue;
    Command back;
    ASSERT_TRUE(decode(encode(c), back));
    EXPECT_EQ(back, c) << v;
  }
}

TEST(FalconProtocol, TheReaderFindsPacketsAcrossReadsAndSkipsGarbage) {
  PacketReader reader;
  const std::string stream = std::string("xx>") + "<AAAAAAAAAAAAAA" + "<BAAAPPPPEDCBAA>" + "<JFKPAAAAAAAAAA>";
  // fed in uneven pieces, as reads return them
  Packet p;
  std::vector<std::string> got;
  for (std::size_t at = 0; at < stream.size(); at += 5) {
    const std::string piece = stream.substr(at, 5);
    reader.feed(reinterpret_cast<const std::uint8_t*>(piece.data()), static_cast<int>(piece.size()));
    while (reader.next(p)) got.push_back(text(p));
  }
  // the truncated first packet (its '<' is followed by another '<' at byte 16) is dropped
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0], "<BAAAPPPPEDCBAA>");
  EXPECT_EQ(got[1], "<JFKPAAAAAAAAAA>");
  EXPECT_EQ(reader.pending(), 0);
}

TEST(FalconProtocol, TheReaderWaitsForTheRestOfAPacket) {
  PacketReader reader;
  const std::string half = "<BAAAPPPP";
  reader.feed(reinterpret_cast<const std::uint8_t*>(half.data()), static_cast<int>(half.size()));
  Packet p;
  EXPECT_FALSE(reader.next(p));
  const std::string rest = "EDCBAA>";
  reader.feed(reinterpret_cast<const std::uint8_t*>(rest.data()), static_cast<int>(rest.size()));
  ASSERT_TRUE(reader.next(p));
  EXPECT_EQ(text(p), "<BAAAPPPPEDCBAA>");
}

}  // namespace
}  // namespace enact::devices::falcon
