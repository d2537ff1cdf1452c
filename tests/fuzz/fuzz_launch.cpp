// The launch file loader with its substitutions ($(arg), $(env), includes, containers) on
// any file: a launch description, or config::Error naming the file and line.
#include <map>
#include <string>

#include "core/config/yaml.h"
#include "core/launch/launch_file.h"
#include "tests/fuzz/fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::map<std::string, std::string> args = {{"rate_hz", "1000"}, {"scene", "scenes/bridge.yaml"}};
  // every executable resolves, as a path when it has a '/'
  const auto resolve = [](const std::string& exec) { return exec.find('/') != std::string::npos ? exec : "/bin/" + exec; };
  try {
    enact::launch::load_launch(enact::fuzz::input_file(data, size, "launch.yaml"), args, resolve);
  } catch (const enact::config::Error&) {
  }
  return 0;
}
