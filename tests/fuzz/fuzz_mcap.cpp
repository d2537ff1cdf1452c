// The MCAP reader on any bytes: it reads what is there, reports damage, and throws only
// record::Error (not MCAP at all).
#include <string>

#include "core/record/reader.h"
#include "tests/fuzz/fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = enact::fuzz::input_file(data, size, "in.mcap");
  try {
    enact::record::Reader reader(path);
    std::size_t bytes = 0;
    reader.for_each([&](const enact::record::Message& m) {
      bytes += m.data.size() + m.topic.size() + m.schema_name.size();
      return true;
    });
    bytes += reader.damage().size() + reader.metadata("enact.params").size();
    bytes += reader.attachment("sim.scene").value_or("").size();
    return bytes == 0 ? 0 : 0;
  } catch (const enact::record::Error&) {
    return 0;
  }
}
