// The computer-model loader on any file: a model, or config::Error naming the file and line.
#include "core/config/yaml.h"
#include "core/haptics/computer_model.h"
#include "tests/fuzz/fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    enact::haptics::resolve_computer_model(enact::fuzz::input_file(data, size, "model.yaml"));
  } catch (const enact::config::Error&) {
  }
  return 0;
}
