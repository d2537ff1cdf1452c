#pragma once
// Fuzz targets: each file defines LLVMFuzzerTestOneInput, built two ways by
// tests/fuzz/CMakeLists.txt: with libFuzzer (clang, ENACT_FUZZ, scripts/fuzz.sh) to search,
// and with replay_main.cpp as an ordinary ctest case replaying tests/fuzz/corpus/NAME.
// A target returns normally for any input a program may refuse; a crash, a sanitizer report
// or an exception other than the documented refusal is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

namespace enact::fuzz {

// writes the input to NAME in a folder of this process (removed at exit) and returns its path
std::string input_file(const std::uint8_t* data, std::size_t size, const std::string& name);

}  // namespace enact::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
