#pragma once
// The one number parser of the project: command lines, node parameters, parameter changes
// and CSV cells all read numbers with it, so "0.5abc", " 1", "" and "nan" mean the same
// everywhere (not a number, or not a finite one). Callers say what was wrong, where, and
// the fix.
#include <optional>
#include <string>
#include <string_view>

namespace enact::config {

// `text` as a double when the whole of it is one decimal number (no spaces, no units, no
// hex); NaN and infinities only when `allow_nonfinite`. nullopt otherwise.
std::optional<double> parse_number(std::string_view text, bool allow_nonfinite = false);

// `text` as a whole number when all of it is one (an optional '-' and digits) and it fits a
// long long; nullopt otherwise
std::optional<long long> parse_integer(std::string_view text);

// the unit a name ends with, as people write it ("Hz" for rate_hz, "N/m" for
// stiffness_n_per_m; "" for none): names carry their unit (docs/parameters.md)
std::string unit_of(std::string_view name);

}  // namespace enact::config
