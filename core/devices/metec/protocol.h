#pragma once
// Metec Braille cells over USB, from public descriptions: BRLTTY's Metec driver
// (Drivers/Braille/Metec/braille.c, The BRLTTY Developers, GPL/LGPL; facts only, our own
// code). USB 0452:0100, configuration 1, interface 0, input endpoint 1. Vendor control
// requests to the device (value 0, index 0):
//   0x01 high voltage: one byte, 0xFF on, 0x7F off (off: every pin drops)
//   0x04 identity request: one byte 0; the identity text then arrives on the input endpoint
//   0x0A + m: the 8 cells of module m, one byte per cell (cells m*8 .. m*8+7)
//   0x80 (device to host): the 8-byte status: [0] routing key pressed (0xFF none), [1] the
//        number of cells, [2..3] navigation keys (little-endian)
// A cell's byte has one bit per dot: dot 1 = 0x80, dot 2 = 0x40, ... dot 8 = 0x01. An 8-dot
// cell has 2 columns x 4 rows of dots: left column dots 1, 2, 3, 7 from the top, right
// column dots 4, 5, 6, 8.
//
// The pin array on the cells (enact's mapping): rows (1..4) x cols (1..8) pins, pin i =
// row * cols + col, row 0 the far row, col 0 the left; pin columns 2k and 2k+1 are the left
// and right dot columns of cell first_cell + k, pin row r is dot row r. A 4 x 4 array is two
// adjacent cells; up to 32 pins: 4 x 8 on four cells side by side.
#include <array>
#include <cstdint>

namespace enact::devices::metec {

constexpr int kConfiguration = 1;
constexpr int kInterface = 0;
constexpr std::uint8_t kEndpointIn = 0x81;

constexpr std::uint8_t kSetHighVoltage = 0x01;
constexpr std::uint8_t kIdentify = 0x04;
constexpr std::uint8_t kWriteModule = 0x0A;  // + module number
constexpr std::uint8_t kGetStatus = 0x80;
constexpr std::uint8_t kHighVoltageOn = 0xFF;
constexpr std::uint8_t kHighVoltageOff = 0x7F;

constexpr int kCellsPerModule = 8;
constexpr int kMaxModules = 10;
constexpr int kStatusSize = 8;
constexpr int kIdentitySize = 256;
constexpr std::uint8_t kNoRoutingKey = 0xFF;

// a dot's bit (dot 1 .. 8)
constexpr std::uint8_t dot_bit(int dot) { return static_cast<std::uint8_t>(0x80u >> (dot - 1)); }
// the dot at (row 0..3, column 0..1) of a cell
constexpr int dot_at(int row, int column) {
  constexpr int kDots[4][2] = {{1, 4}, {2, 5}, {3, 6}, {7, 8}};
  return kDots[row][column];
}

struct DisplayStatus {
  std::uint8_t routing_key = kNoRoutingKey;
  int cells = 0;
  std::uint16_t navigation_keys = 0;
};
DisplayStatus decode_status(const std::array<std::uint8_t, kStatusSize>& bytes);
std::array<std::uint8_t, kStatusSize> encode_status(const DisplayStatus& status);  // the emulator's side

// where the pin array sits on the display
struct Layout {
  int rows = 4;
  int cols = 4;
  int first_cell = 0;
  int pins() const { return rows * cols; }
  int cells() const { return (cols + 1) / 2; }  // cells used
  int first_module() const { return first_cell / kCellsPerModule; }
  int last_module() const { return (first_cell + cells() - 1) / kCellsPerModule; }
  bool operator==(const Layout&) const = default;
};

// the display cells of a pin word: cells[k] is cell first_cell + k, k < cells() (bits of
// pins beyond rows * cols are ignored)
void cells_of(const Layout& layout, std::uint32_t pins, std::uint8_t* cells);
// the pin word the cells show (the inverse)
std::uint32_t pins_of(const Layout& layout, const std::uint8_t* cells);
// the cell (absolute) and dot of a pin
struct CellDot {
  int cell = 0;
  int dot = 1;
};
CellDot cell_dot(const Layout& layout, int pin);

}  // namespace enact::devices::metec
