#include "core/config/number.h"

#include <charconv>
#include <cmath>

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

}  // namespace enact::config
