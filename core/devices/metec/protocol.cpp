#include "core/devices/metec/protocol.h"

namespace enact::devices::metec {

DisplayStatus decode_status(const std::array<std::uint8_t, kStatusSize>& b) {
  return {b[0], b[1], static_cast<std::uint16_t>(b[2] | (b[3] << 8))};
}

std::array<std::uint8_t, kStatusSize> encode_status(const DisplayStatus& s) {
  return {s.routing_key, static_cast<std::uint8_t>(s.cells), static_cast<std::uint8_t>(s.navigation_keys & 0xFF),
          static_cast<std::uint8_t>(s.navigation_keys >> 8), 0, 0, 0, 0};
}

CellDot cell_dot(const Layout& layout, int pin) {
  const int row = pin / layout.cols, col = pin % layout.cols;
  return {layout.first_cell + col / 2, dot_at(row, col % 2)};
}

void cells_of(const Layout& layout, std::uint32_t pins, std::uint8_t* cells) {
  for (int k = 0; k < layout.cells(); ++k) cells[k] = 0;
  for (int pin = 0; pin < layout.pins(); ++pin) {
    if (((pins >> pin) & 1u) == 0) continue;
    const CellDot cd = cell_dot(layout, pin);
    cells[cd.cell - layout.first_cell] |= dot_bit(cd.dot);
  }
}

std::uint32_t pins_of(const Layout& layout, const std::uint8_t* cells) {
  std::uint32_t pins = 0;
  for (int pin = 0; pin < layout.pins(); ++pin) {
    const CellDot cd = cell_dot(layout, pin);
    if (cells[cd.cell - layout.first_cell] & dot_bit(cd.dot)) pins |= 1u << pin;
  }
  return pins;
}

}  // namespace enact::devices::metec
