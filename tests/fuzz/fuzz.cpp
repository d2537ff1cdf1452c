#include "tests/fuzz/fuzz.h"

#include <fstream>

#include "tests/support/test_util.h"

namespace enact::fuzz {

std::string input_file(const std::uint8_t* data, std::size_t size, const std::string& name) {
  static const test::TempDir dir;
  const std::string path = dir.file(name);
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace enact::fuzz
