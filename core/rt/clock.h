#pragma once
// The loop's time base: CLOCK_MONOTONIC in int64 nanoseconds (DESIGN.md, "times are int64
// nanoseconds of a monotonic clock"), and an absolute sleep on that clock.
#include <cstdint>
#include <optional>
#include <string_view>

namespace enact::rt {

// CLOCK_MONOTONIC now, in ns: the one clock of enact (loops, header.stamp_ns, the launcher).
// Allocates nothing, never throws.
std::int64_t now_ns() noexcept;

// CLOCK_REALTIME now, in ns since 1970: for the dates tools show (log times in recordings,
// message times in Foxglove), never for a loop or a stamp. Allocates nothing, never throws.
std::int64_t wall_ns() noexcept;

// a clock to read instead of now_ns (tests and emulators drive time with their own)
using ClockFn = std::int64_t (*)();

// the graph clock (launch entry `clock:`, option --clock), as ROS 2's use_sim_time: real
// time, where the clock master ticks on the deadlines of rate_hz, or simulated time, where it
// ticks as soon as the tick before is done (no sleeping, no deadline to miss). In both, a
// tick's time is its deadline: tick n is at n / rate_hz from the first, so the model, the
// simulated devices and a virtual subject see the same times in either clock.
enum class GraphClock : std::uint8_t { real, simulated };
// "real" or "simulated"
const char* to_string(GraphClock clock);
// the clock named "real" or "simulated"; nullopt for any other text
std::optional<GraphClock> parse_clock(std::string_view text);

// milliseconds from now until `deadline_ns`, rounded up (so a wait of that many ms never
// ends before the deadline), 0 once it has passed. For APIs that take ms (zmq_poll).
int ms_until(std::int64_t deadline_ns) noexcept;

// sleep until the absolute CLOCK_MONOTONIC time `deadline_ns` (clock_nanosleep, TIMER_ABSTIME);
// a signal does not cut it short. Returns at once for a time already past.
void sleep_until_ns(std::int64_t deadline_ns);

}  // namespace enact::rt
