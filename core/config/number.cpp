#include "core/config/number.h"

#include <charconv>
#include <cmath>
#include <utility>

namespace enact::config {

std::optional<double> parse_number(std::string_view text, bool allow_nonfinite) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [at, error] = std::from_chars(text.data(), end, value, std::chars_format::general);
  if (text.empty() || error != std::errc() || at != end) return std::nullopt;
  if (!allow_nonfinite && !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<long long> parse_integer(std::string_view text) {
  long long value = 0;
  const char* end = text.data() + text.size();
  const auto [at, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || at != end) return std::nullopt;
  return value;
}

std::string unit_of(std::string_view name) {
  // longest suffix first
  static const std::pair<const char*, const char*> kUnits[] = {
      {"_n_s_per_m", "N s/m"}, {"_n_per_m", "N/m"}, {"_m_per_s", "m/s"}, {"_n_per_ms", "N/ms"}, {"_hz", "Hz"}, {"_us", "us"}, {"_ms", "ms"},
      {"_mb", "MB"}, {"_kg", "kg"}, {"_s", "s"}, {"_m", "m"}, {"_n", "N"},
  };
  for (const auto& [suffix, unit] : kUnits) {
    if (name.ends_with(suffix)) return unit;
  }
  return "";
}

}  // namespace enact::config
