#pragma once
// Comma-separated lists, as the command line and node parameters write them ("CM0,CM1").
#include <sstream>
#include <string>
#include <vector>

namespace enact::config {

// the items of a comma-separated list, empty items left out
inline std::vector<std::string> split_commas(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace enact::config
