#include "core/rt/scheduler.h"

#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/rt/loop_stats.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/config/format.h"
#include "core/config/yaml.h"
#include "core/rt/clock.h"

namespace enact::rt {
namespace {

// one second in ns times one hertz in mHz: the period in ns is kPeriodScale / rate_mhz
constexpr std::int64_t kPeriodScale = 1'000'000'000'000;

// tell the core we are spinning (lets a sibling hyperthread run, saves power)
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

}  // namespace

void SchedulerParams::validate() const {
  if (!(rate_hz >= kMinRate_hz && rate_hz <= kMaxRate_hz)) {
    throw config::Error("scheduler: rate_hz " + config::number(rate_hz) +
                        " is out of range\n  fix: use a rate_hz from 1 to 44000 Hz (5000 is the seed system's)");
  }
  if (spin_ns < 0) {
    throw config::Error("scheduler: spin_ns " + std::to_string(spin_ns) +
                        " is negative\n  fix: use 0 (sleep only) or a positive time to spin before each deadline, e.g. 50000");
  }
}

PeriodicScheduler::PeriodicScheduler(SchedulerParams params) : params_(params) {
  params_.validate();
  rate_mhz_ = std::llround(params_.rate_hz * 1000.0);
  period_whole_ns_ = kPeriodScale / rate_mhz_;
  period_rem_ = kPeriodScale % rate_mhz_;
  period_ns_ = (kPeriodScale + rate_mhz_ / 2) / rate_mhz_;
  spin_ns_ = params_.sleep_every_tick ? std::min(params_.spin_ns, period_ns_ / 2) : params_.spin_ns;
  if (params_.wake_fd && !params_.simulated) {
    timer_fd_ = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
    if (timer_fd_ < 0) throw config::Error(std::string("the loop's timer (timerfd_create): ") + std::strerror(errno));
  }
}

PeriodicScheduler::~PeriodicScheduler() {
  if (timer_fd_ >= 0) close(timer_fd_);
}

void PeriodicScheduler::arm(std::int64_t t) {
  const itimerspec when{{0, 0}, {static_cast<time_t>(t / 1'000'000'000), static_cast<long>(t % 1'000'000'000)}};
  armed_ns_ = timerfd_settime(timer_fd_, TFD_TIMER_ABSTIME, &when, nullptr) == 0 ? t : -1;
}

void PeriodicScheduler::sleep_until(std::int64_t t) {
  if (timer_fd_ < 0) {
    sleep_until_ns(t);
    return;
  }
  // the timer fires at t (armed while the tick before spun), or is set for it now (a tick
  // skipped); a read waits for it to fire (at once when it has)
  while (now_ns() < t) {
    if (armed_ns_ != t) arm(t);
    std::uint64_t fired = 0;
    const bool slept = armed_ns_ == t && (read(timer_fd_, &fired, sizeof fired) >= 0 || errno == EINTR);
    if (!slept) {
      sleep_until_ns(t);  // no timer: sleep as without one
      return;
    }
  }
}

void PeriodicScheduler::start(std::int64_t first_deadline_ns) {
  started_ = true;
  first_ns_ = first_deadline_ns;
  index_ = 0;
  next_index_ = 0;
  deadline_ns_ = first_deadline_ns;
  ticks_ = 0;
  overruns_ = 0;
  skipped_ = 0;
  jitter_.reset();
}

std::int64_t PeriodicScheduler::deadline_at(std::int64_t n) const {
  // floor(n * 1e12 / rate_mhz) without overflow: n = whole * rate_mhz + part, part < rate_mhz
  const std::int64_t whole = n / rate_mhz_;
  const std::int64_t part = n % rate_mhz_;
  return first_ns_ + whole * kPeriodScale + part * period_whole_ns_ + part * period_rem_ / rate_mhz_;
}

std::int64_t PeriodicScheduler::first_index_after(std::int64_t t) const {
  // estimate in floating point, then settle exactly on the integer deadlines
  const double period = static_cast<double>(kPeriodScale) / static_cast<double>(rate_mhz_);
  std::int64_t n = std::max(index_ + 1, static_cast<std::int64_t>(static_cast<double>(t - first_ns_) / period));
  while (deadline_at(n) <= t) ++n;
  while (n > index_ + 1 && deadline_at(n - 1) > t) --n;
  return n;
}

std::int64_t PeriodicScheduler::wait() {
  if (!started_) start(now_ns());
  index_ = next_index_;
  deadline_ns_ = deadline_at(index_);
  if (params_.simulated) {
    jitter_.record(0);
    ++ticks_;
    next_index_ = index_ + 1;
    return deadline_ns_;
  }
  // sleep to just before the deadline, then spin on the clock to it
  const std::int64_t sleep_to = deadline_ns_ - spin_ns_;
  std::int64_t woke = now_ns();
  last_sleep_late_ns_ = -1;
  if (woke < sleep_to) {
    sleep_until(sleep_to);
    woke = now_ns();
    last_sleep_late_ns_ = woke - sleep_to;
  }
  // the timer for the next sleep, set within this spin window, before the tick's work
  if (timer_fd_ >= 0) {
    arm(deadline_at(index_ + 1) - spin_ns_);
    woke = now_ns();
  }
  while (woke < deadline_ns_) {
    cpu_relax();
    woke = now_ns();
  }
  jitter_.record(woke - deadline_ns_);
  ++ticks_;
  // woke at or past the following deadline: an overrun; skip to the first deadline ahead
  next_index_ = index_ + 1;
  if (deadline_at(next_index_) <= woke) {
    next_index_ = first_index_after(woke);
    const auto skipped = static_cast<std::uint64_t>(next_index_ - index_ - 1);
    skipped_ += skipped;
    overruns_ += 1 + skipped;
    if (timer_fd_ >= 0) arm(deadline_at(next_index_) - spin_ns_);  // a later sleep than the one armed
  }
  return woke;
}

void take_timing(const PeriodicScheduler& scheduler, LoopStats& stats) {
  stats.jitter = scheduler.jitter();
  stats.overruns = scheduler.overruns();
  stats.ticks = scheduler.ticks();
}

}  // namespace enact::rt
