#include "core/rt/clock.h"

#include <cerrno>
#include <climits>
#include <ctime>

namespace enact::rt {
namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;

}  // namespace

std::int64_t now_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

const char* to_string(GraphClock clock) { return clock == GraphClock::simulated ? "simulated" : "real"; }

std::optional<GraphClock> parse_clock(std::string_view text) {
  if (text == "real") return GraphClock::real;
  if (text == "simulated") return GraphClock::simulated;
  return std::nullopt;
}

std::int64_t wall_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

int ms_until(std::int64_t deadline_ns) noexcept {
  constexpr std::int64_t kNsPerMs = 1'000'000;
  const std::int64_t left = deadline_ns - now_ns();
  if (left <= 0) return 0;
  const std::int64_t ms = (left + kNsPerMs - 1) / kNsPerMs;
  return ms > INT_MAX ? INT_MAX : static_cast<int>(ms);
}

void sleep_until_ns(std::int64_t deadline_ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline_ns / kNsPerS);
  ts.tv_nsec = static_cast<long>(deadline_ns % kNsPerS);
  // an absolute deadline: restarting after a signal neither drifts nor sleeps twice
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace enact::rt
