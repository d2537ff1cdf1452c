#include "nodes/enact/play_clock.h"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <ctime>

#include "core/graph/stop.h"
#include "core/rt/clock.h"

namespace enact::cli {
namespace {

// the terminal's mode before raw mode, for the signal handlers
struct termios g_saved;
struct termios g_raw;

void restore_terminal() { tcsetattr(STDIN_FILENO, TCSAFLUSH, &g_saved); }

// a signal that ends or stops the process: the terminal restored, then its own action
void restore_and_raise(int sig) {
  restore_terminal();
  signal(sig, SIG_DFL);
  raise(sig);
}

// back from Ctrl-Z: raw again, the handler put back
void on_continue(int) {
  tcsetattr(STDIN_FILENO, TCSAFLUSH, &g_raw);
  signal(SIGTSTP, restore_and_raise);
}

constexpr int kRestoringSignals[] = {SIGHUP, SIGQUIT, SIGABRT, SIGTSTP};

}  // namespace

TerminalKeys::TerminalKeys(bool enabled) {
  if (!enabled || !isatty(STDIN_FILENO) || tcgetattr(STDIN_FILENO, &g_saved) != 0) return;
  g_raw = g_saved;
  g_raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
  g_raw.c_cc[VMIN] = 1;
  g_raw.c_cc[VTIME] = 0;
  for (const int sig : kRestoringSignals) signal(sig, restore_and_raise);
  signal(SIGCONT, on_continue);
  active_ = tcsetattr(STDIN_FILENO, TCSAFLUSH, &g_raw) == 0;
}

TerminalKeys::~TerminalKeys() {
  if (!active_) return;
  restore_terminal();
  for (const int sig : kRestoringSignals) signal(sig, SIG_DFL);
  signal(SIGCONT, SIG_DFL);
}

std::optional<char> TerminalKeys::key(std::int64_t timeout_ns) {
  pollfd p{STDIN_FILENO, POLLIN, 0};
  const timespec ts{static_cast<time_t>(timeout_ns / 1'000'000'000), static_cast<long>(timeout_ns % 1'000'000'000)};
  char c = 0;
  if (!active_ || ppoll(&p, 1, &ts, nullptr) != 1 || read(STDIN_FILENO, &c, 1) != 1) {
    if (!active_) rt::sleep_until_ns(rt::now_ns() + timeout_ns);
    return std::nullopt;
  }
  return c;
}

PlayClock::PlayClock(double rate, TerminalKeys& keys, std::function<void()> on_change) : rate_(rate), keys_(keys), on_change_(std::move(on_change)) {}

void PlayClock::restart(std::int64_t first_log_ns) {
  first_log_ns_ = first_log_ns;
  wall0_ns_ = rt::now_ns();
  paused_at_ns_ = wall0_ns_;
}

std::int64_t PlayClock::offset_ns(std::int64_t log_ns) const {
  return rate_ > 0.0 ? static_cast<std::int64_t>(static_cast<double>(log_ns - first_log_ns_) / rate_) : 0;
}

void PlayClock::set_paused(bool paused) {
  if (paused == paused_) return;
  const std::int64_t now = rt::now_ns();
  // the time paused is left out of the timing
  if (paused) paused_at_ns_ = now;
  else wall0_ns_ += now - paused_at_ns_;
  paused_ = paused;
  steps_ = 0;
  on_change_();
}

void PlayClock::answer_keys(std::int64_t timeout_ns) {
  const auto k = keys_.key(timeout_ns);
  if (k == ' ') set_paused(!paused_);
  if (k == 's' && paused_) ++steps_;
}

bool PlayClock::wait(std::int64_t log_ns) {
  constexpr std::int64_t kKeyPoll_ns = 100'000'000;
  while (!graph::stop_requested()) {
    const std::int64_t now = rt::now_ns();
    if (paused_) {
      if (steps_ == 0) {
        answer_keys(kKeyPoll_ns);
        continue;
      }
      // one step: this message is due now, and the timing goes on from it
      --steps_;
      wall0_ns_ = now - offset_ns(log_ns);
      paused_at_ns_ = now;
      return true;
    }
    const std::int64_t due = wall0_ns_ + offset_ns(log_ns);
    if (now >= due) return true;
    // the last stretch slept exactly; the rest listening to the keys
    if (!keys_.active() || due - now < 1'000'000) {
      rt::sleep_until_ns(std::min(due, now + kKeyPoll_ns));
      continue;
    }
    answer_keys(std::min(due - now, kKeyPoll_ns));
  }
  return false;
}

}  // namespace enact::cli
