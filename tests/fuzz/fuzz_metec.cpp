// The Metec cells' status bytes and the pin mapping on any bytes: decoding never fails, and
// pins survive the trip through the cells for every layout the device accepts.
#include <array>
#include <cstring>

#include "core/devices/metec/protocol.h"
#include "tests/fuzz/fuzz.h"

using namespace enact::devices::metec;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::array<std::uint8_t, kStatusSize> status{};
  std::memcpy(status.data(), data, std::min<std::size_t>(size, status.size()));
  const DisplayStatus s = decode_status(status);
  if (s.cells < 0) __builtin_trap();
  if (size < kStatusSize + 7) return 0;
  // a layout within the device's limits (rows 1..4, cols 1..8, cells on the display)
  const std::uint8_t* p = data + kStatusSize;
  Layout layout;
  layout.rows = 1 + p[0] % 4;
  layout.cols = 1 + p[1] % 8;
  layout.first_cell = p[2] % (kCellsPerModule * kMaxModules - layout.cells() + 1);
  std::uint32_t pins = 0;
  std::memcpy(&pins, p + 3, sizeof pins);
  pins &= layout.pins() == 32 ? 0xFFFFFFFFu : (1u << layout.pins()) - 1;
  std::array<std::uint8_t, kCellsPerModule * kMaxModules> cells{};
  cells_of(layout, pins, cells.data());
  if (pins_of(layout, cells.data()) != pins) __builtin_trap();
  return 0;
}
