// The path CSV reader on any file: a trajectory (then sampled anywhere), or config::Error
// naming the file and line.
#include "core/config/yaml.h"
#include "core/task/trajectory.h"
#include "tests/fuzz/fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto path = enact::task::load_trajectory(enact::fuzz::input_file(data, size, "path.csv"));
    for (const double t : {-1e300, path.start_s(), 0.5 * (path.start_s() + path.end_s()), path.end_s(), 1e300}) path.at(t);
  } catch (const enact::config::Error&) {
  }
  return 0;
}
