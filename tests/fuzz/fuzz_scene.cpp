// The scene loader on any file: a model, or config::Error naming the file and line.
#include "core/config/yaml.h"
#include "core/physics/scene.h"
#include "tests/fuzz/fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    enact::physics::load_scene(enact::fuzz::input_file(data, size, "scene.yaml"));
  } catch (const enact::config::Error&) {
  }
  return 0;
}
