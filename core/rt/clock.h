#pragma once
// The loop's time base: CLOCK_MONOTONIC in int64 nanoseconds (DESIGN.md, "times are int64
// nanoseconds of a monotonic clock"), and an absolute sleep on that clock.
#include <cstdint>

namespace enact::rt {

// CLOCK_MONOTONIC now, in ns. Allocates nothing, never throws.
std::int64_t now_ns();

// sleep until the absolute CLOCK_MONOTONIC time `deadline_ns` (clock_nanosleep, TIMER_ABSTIME);
// a signal does not cut it short. Returns at once for a time already past.
void sleep_until_ns(std::int64_t deadline_ns);

}  // namespace enact::rt
