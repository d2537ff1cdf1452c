#pragma once
// Number formatting shared by every file writer: shortest text that reads back to 9
// significant digits, identical on every run (byte-identical outputs).
#include <cstdio>
#include <string>

namespace enact::config {

inline std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace enact::config
