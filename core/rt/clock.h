#pragma once
// The loop's time base: CLOCK_MONOTONIC in int64 nanoseconds (DESIGN.md, "times are int64
// nanoseconds of a monotonic clock"), and an absolute sleep on that clock.
#include <cstdint>

namespace enact::rt {

// CLOCK_MONOTONIC now, in ns: the one clock of enact (loops, header.stamp_ns, the launcher).
// Allocates nothing, never throws.
std::int64_t now_ns() noexcept;

// CLOCK_REALTIME now, in ns since 1970: for the dates tools show (log times in recordings,
// message times in Foxglove), never for a loop or a stamp. Allocates nothing, never throws.
std::int64_t wall_ns() noexcept;

// a clock to read instead of now_ns (tests and emulators drive time with their own)
using ClockFn = std::int64_t (*)();

// milliseconds from now until `deadline_ns`, rounded up (so a wait of that many ms never
// ends before the deadline), 0 once it has passed. For APIs that take ms (zmq_poll).
int ms_until(std::int64_t deadline_ns) noexcept;

// sleep until the absolute CLOCK_MONOTONIC time `deadline_ns` (clock_nanosleep, TIMER_ABSTIME);
// a signal does not cut it short. Returns at once for a time already past.
void sleep_until_ns(std::int64_t deadline_ns);

}  // namespace enact::rt
