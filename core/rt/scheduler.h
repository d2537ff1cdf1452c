#pragma once
// The periodic scheduler of the real-time loop: wakes the loop thread at absolute deadlines
// on CLOCK_MONOTONIC, sleeping to just before each one and spinning the rest, and measures
// how late each wake-up was.
//
// Deadlines never drift: deadline n = first + floor(n * 1e9 / rate_hz) ns, computed exactly in
// integers from n (never by adding a rounded period), with the rate taken to the millihertz.
// At 3 kHz the period is 333333.33 ns and deadline 3000 is exactly first + 1 s.
//
// Overruns: when a wake-up comes at or after the following deadline (late by a whole period
// or more), the deadlines already past are skipped: the next wait() waits for the first
// deadline still ahead, it never runs missed ticks back to back. Every missed deadline is an
// overrun: the late one and each one skipped (a 50 ms stall at 44 kHz is 2200 overruns).
//
// Simulated time (GraphClock::simulated): wait() returns the next deadline at once, without
// reading the clock or sleeping: the deadlines are the tick's times, none is ever missed.
#include <cstdint>

#include "core/rt/histogram.h"

namespace enact::rt {

// the loop rates a scheduler accepts (Hz)
inline constexpr double kMinRate_hz = 1.0;
inline constexpr double kMaxRate_hz = 44'000.0;

struct SchedulerParams {
  double rate_hz = 5000.0;       // loop rate, 1..44000 Hz
  std::int64_t spin_ns = 50'000;  // spin on the clock for this long before each deadline (>= 0)
  // spin at most half a period, so the thread sleeps every tick: a SCHED_FIFO thread that
  // never sleeps is throttled by the kernel (sched_rt_runtime_us: ~50 ms stalled each second)
  bool sleep_every_tick = false;
  // simulated time: never wait, never late (see above)
  bool simulated = false;
  // sleep on a timer the loop can wait on beside its sockets (reply_wait(), below)
  bool wake_fd = false;

  // throws config::Error naming the parameter and the fix
  void validate() const;
};

class PeriodicScheduler {
 public:
  // validates the params (config::Error) and allocates the jitter histogram
  explicit PeriodicScheduler(SchedulerParams params);
  ~PeriodicScheduler();
  PeriodicScheduler(const PeriodicScheduler&) = delete;
  PeriodicScheduler& operator=(const PeriodicScheduler&) = delete;

  // (re)start: deadline 0 is first_deadline_ns; counters and the histogram are cleared
  void start(std::int64_t first_deadline_ns);
  // wait for the next deadline; returns the time it woke (now_ns(), never before the
  // deadline; in simulated time the deadline itself, at once). Records the lateness in jitter(), counts overruns and skips missed deadlines
  // (see above). Allocates nothing, never throws. Before start(): starts at now.
  std::int64_t wait();

  // the absolute deadline of index n (the drift-free formula above)
  std::int64_t deadline_at(std::int64_t n) const;

  // the nominal period, rounded to the nearest ns (deadlines use the exact fraction)
  std::int64_t period_ns() const { return period_ns_; }
  double rate_hz() const { return params_.rate_hz; }
  // wake-ups so far (calls to wait())
  std::uint64_t ticks() const { return ticks_; }
  // deadlines missed: wake-ups that came a whole period or more late, plus skipped()
  std::uint64_t overruns() const { return overruns_; }
  // deadlines skipped (never woken for) because of late wake-ups
  std::uint64_t skipped() const { return skipped_; }
  // the spin window in use (spin_ns, capped at half a period with sleep_every_tick)
  std::int64_t spin_ns() const { return spin_ns_; }
  // how late the last wait() came out of its sleep (woke - deadline + spin window), before
  // any spin; -1 when it did not sleep (already inside the spin window)
  std::int64_t last_sleep_late_ns() const { return last_sleep_late_ns_; }
  // wake-up lateness (woke - deadline) of every tick, ns
  const LatencyHistogram& jitter() const { return jitter_; }
  // the deadline the last wait() woke for, and its index
  std::int64_t deadline_ns() const { return deadline_ns_; }
  std::int64_t deadline_index() const { return index_; }
  // the deadline the next wait() will wait for
  std::int64_t next_deadline_ns() const { return deadline_at(next_index_); }
  // how a loop waits for a reply until t, when the next wait() is due to stop sleeping (t =
  // next_deadline_ns() - spin_ns()). With SchedulerParams::wake_fd the scheduler's timer
  // (a timerfd, armed while this tick spun) becomes readable at t: poll stop_fd beside the
  // socket, with `until` a far backstop, and the wait arms no timer of its own, which on a VM
  // costs each wait some us as the timer is set and again as it is cancelled. Otherwise (or
  // when the timer is not armed for t): until = t, stop_fd = -1
  struct ReplyWait {
    std::int64_t until;
    int stop_fd;
  };
  ReplyWait reply_wait(std::int64_t t) const { return armed_ns_ == t && timer_fd_ >= 0 ? ReplyWait{t + kReplyBackstop_ns, timer_fd_} : ReplyWait{t, -1}; }
  // the backstop past t, should the timer fail (a timeout 1 ms or more ahead cost this VM
  // nothing measurable; 300 us ahead, ~10 us a round trip: enact bench loop)
  static constexpr std::int64_t kReplyBackstop_ns = 2'000'000;

 private:
  // the first index whose deadline is after t
  std::int64_t first_index_after(std::int64_t t) const;
  // sleeps until t (the timer armed for it unless it already is)
  void sleep_until(std::int64_t t);
  void arm(std::int64_t t);

  SchedulerParams params_;
  // 1e12 / rate_mhz_ = period_whole_ns_ + period_rem_ / rate_mhz_: the exact period
  std::int64_t rate_mhz_ = 0;
  std::int64_t period_whole_ns_ = 0;
  std::int64_t period_rem_ = 0;
  std::int64_t period_ns_ = 0;
  std::int64_t spin_ns_ = 0;
  std::int64_t last_sleep_late_ns_ = -1;

  bool started_ = false;
  std::int64_t first_ns_ = 0;
  std::int64_t index_ = 0;
  std::int64_t next_index_ = 0;
  std::int64_t deadline_ns_ = 0;
  std::uint64_t ticks_ = 0;
  std::uint64_t overruns_ = 0;
  std::uint64_t skipped_ = 0;
  LatencyHistogram jitter_;
  int timer_fd_ = -1;
  std::int64_t armed_ns_ = -1;  // when the timer fires next (-1: not armed)
};

// the scheduler's timing (jitter histogram, overruns, ticks) into a loop's stats
struct LoopStats;
void take_timing(const PeriodicScheduler& scheduler, LoopStats& stats);

}  // namespace enact::rt
