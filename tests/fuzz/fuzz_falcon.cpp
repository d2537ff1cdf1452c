// The Falcon's byte stream: any bytes from the device, in any chunking, through the packet
// reader and both decoders (the host's and the emulator's).
#include <algorithm>

#include "core/devices/falcon/protocol.h"
#include "tests/fuzz/fuzz.h"

using namespace enact::devices::falcon;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // the first byte sets the chunk length (as USB reads would cut the stream)
  const std::size_t chunk = std::max<std::size_t>(1, data[0]);
  PacketReader reader;
  Packet packet{};
  for (std::size_t at = 1; at < size; at += chunk) {
    reader.feed(data + at, static_cast<int>(std::min(chunk, size - at)));
    while (reader.next(packet)) {
      Reading reading;
      Command command;
      Reading again;
      // a valid answer survives encoding again
      if (decode(packet, reading) && (!decode(encode(reading), again) || !(again == reading))) __builtin_trap();
      decode(packet, command);
    }
  }
  return 0;
}
