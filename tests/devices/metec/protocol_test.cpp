// The Metec cells' bytes against the public description (BRLTTY's Metec driver: dot 1 = 0x80
// ... dot 8 = 0x01; the status packet), and enact's pin-to-dot mapping written out by hand.
#include "core/devices/metec/protocol.h"

#include <gtest/gtest.h>

#include <array>

namespace enact::devices::metec {
namespace {

std::array<std::uint8_t, 4> cells(const Layout& layout, std::uint32_t pins) {
  std::array<std::uint8_t, 4> c{};
  cells_of(layout, pins, c.data());
  return c;
}

TEST(MetecProtocol, DotBitsFollowBrlttysTable) {
  const std::uint8_t want[8] = {0x80, 0x40, 0x20, 0x10, 0x08, 0x04, 0x02, 0x01};
  for (int dot = 1; dot <= 8; ++dot) EXPECT_EQ(dot_bit(dot), want[dot - 1]) << dot;
  // an 8-dot cell: left column 1, 2, 3, 7; right column 4, 5, 6, 8
  EXPECT_EQ(dot_at(0, 0), 1);
  EXPECT_EQ(dot_at(2, 0), 3);
  EXPECT_EQ(dot_at(3, 0), 7);
  EXPECT_EQ(dot_at(0, 1), 4);
  EXPECT_EQ(dot_at(3, 1), 8);
}

TEST(MetecProtocol, TheFourByFourArrayIsTwoAdjacentCells) {
  const Layout l{4, 4, 0};
  EXPECT_EQ(l.cells(), 2);
  // pin i = row * 4 + col; columns 0-1 on cell 0, columns 2-3 on cell 1
  EXPECT_EQ(cells(l, 1u << 0), (std::array<std::uint8_t, 4>{0x80, 0x00}));   // row 0 col 0: dot 1
  EXPECT_EQ(cells(l, 1u << 1), (std::array<std::uint8_t, 4>{0x10, 0x00}));   // row 0 col 1: dot 4
  EXPECT_EQ(cells(l, 1u << 2), (std::array<std::uint8_t, 4>{0x00, 0x80}));   // row 0 col 2: cell 1 dot 1
  EXPECT_EQ(cells(l, 1u << 7), (std::array<std::uint8_t, 4>{0x00, 0x08}));   // row 1 col 3: cell 1 dot 5
  EXPECT_EQ(cells(l, 1u << 12), (std::array<std::uint8_t, 4>{0x02, 0x00}));  // row 3 col 0: dot 7
  EXPECT_EQ(cells(l, 1u << 15), (std::array<std::uint8_t, 4>{0x00, 0x01}));  // row 3 col 3: cell 1 dot 8
  // the left pin column (pins 0, 4, 8, 12): dots 1, 2, 3, 7 of cell 0
  EXPECT_EQ(cells(l, 0x1111), (std::array<std::uint8_t, 4>{0xE2, 0x00}));
  EXPECT_EQ(cells(l, 0xFFFF), (std::array<std::uint8_t, 4>{0xFF, 0xFF}));
}

TEST(MetecProtocol, ThirtyTwoPinsAreFourCellsAndMappingRoundTrips) {
  const Layout l{4, 8, 3};
  EXPECT_EQ(l.cells(), 4);
  EXPECT_EQ(cells(l, 0xFFFFFFFFu), (std::array<std::uint8_t, 4>{0xFF, 0xFF, 0xFF, 0xFF}));
  EXPECT_EQ(cell_dot(l, 31).cell, 6);  // row 3, col 7: the fourth cell from cell 3
  EXPECT_EQ(cell_dot(l, 31).dot, 8);
  // cells 3 .. 6: modules 0 (cells 0-7)
  EXPECT_EQ(l.first_module(), 0);
  EXPECT_EQ(l.last_module(), 0);
  for (std::uint32_t pins : {0u, 1u, 0xA5A5A5A5u, 0x12345678u, 0xFFFFFFFFu}) {
    std::array<std::uint8_t, 4> c{};
    cells_of(l, pins, c.data());
    EXPECT_EQ(pins_of(l, c.data()), pins);
  }
  // two rows x three columns: cells 0 and 1, the second half-used; pins beyond 6 ignored
  const Layout small{2, 3, 0};
  EXPECT_EQ(small.cells(), 2);
  EXPECT_EQ(cells(small, 0xFFFFFFFFu), (std::array<std::uint8_t, 4>{0xD8, 0xC0}));  // dots 1, 2, 4, 5 | dots 1, 2
}

TEST(MetecProtocol, ModulesAreEightCells) {
  const Layout across{4, 4, 7};  // cells 7 and 8
  EXPECT_EQ(across.first_module(), 0);
  EXPECT_EQ(across.last_module(), 1);
}

TEST(MetecProtocol, TheStatusPacketCarriesTheCellCountAndKeys) {
  const std::array<std::uint8_t, 8> bytes = {0x05, 40, 0x34, 0x12, 0, 0, 0, 0};
  const DisplayStatus s = decode_status(bytes);
  EXPECT_EQ(s.routing_key, 5);
  EXPECT_EQ(s.cells, 40);
  EXPECT_EQ(s.navigation_keys, 0x1234);
  EXPECT_EQ(encode_status(s), bytes);
}

}  // namespace
}  // namespace enact::devices::metec
