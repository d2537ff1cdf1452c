// The Inverse Service's messages (core/devices/inverse3/protocol.h) on any text: parsing an
// update or an event never throws (a message the service sends is not trusted to be well
// formed), and a parsed update's devices can always be answered with a force command.
#include <string>

#include "core/devices/inverse3/protocol.h"
#include "tests/fuzz/fuzz.h"

using namespace enact::devices::inverse3;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Update u;
  std::string why;
  if (parse_update(text, u, why)) {
    for (const DeviceEntry& d : u.inverse3) {
      if (force_command(d.device_id, d.position_m).empty()) __builtin_trap();
    }
  } else if (why.empty()) {
    __builtin_trap();  // a refusal always says why
  }
  Event e;
  parse_event(text, e);
  return 0;
}
