#pragma once
// The message of a refusal: what a loader or a check says when it refuses its input
// (config::Error: "FILE:LINE: problem\n  fix: ..."), for tests that check it names the
// file, the line and the fix.
#include <string>

#include "core/config/yaml.h"
#include "tests/support/test_util.h"

namespace enact::test {

// the message of the config::Error that f() throws; "" when it throws none
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const config::Error& e) {
    return e.what();
  }
  return "";
}

// the message of the config::Error that load(path) throws for a file `name` holding `text`
// (in a fresh folder); "" when it loads
template <class Load>
std::string error_of_file(const std::string& name, const std::string& text, Load&& load) {
  const TempDir dir;
  write_file(dir.file(name), text);
  return error_of([&] { load(dir.file(name)); });
}

}  // namespace enact::test
