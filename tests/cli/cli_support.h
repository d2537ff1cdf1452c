#pragma once
// Helpers for the command-line tests: running `enact`, reading values out of its output.
#include <string>

#include "tests/support/test_util.h"

namespace enact::test {

// `enact <args>` (ENACT_CLI), stdout and stderr captured
inline RunResult enact(const std::string& args) { return run(std::string(ENACT_CLI) + " " + args); }

inline std::string bridge_scene() { return source_path("launch/scenes/bridge.yaml"); }

// the raw text of a top-level value in the metrics JSON ("key": value,), empty when absent
inline std::string json_value(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\": ";
  const auto at = json.find(tag);
  if (at == std::string::npos) return {};
  const auto begin = at + tag.size();
  return json.substr(begin, json.find_first_of(",\n}", begin) - begin);
}

}  // namespace enact::test
