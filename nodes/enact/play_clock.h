#pragma once
// enact play's clock: the recorded timing scaled by --rate, held while paused, and the keys
// that pause it from a terminal (Space: pause / resume, s: one message while paused).
#include <termios.h>

#include <cstdint>
#include <functional>
#include <optional>

namespace enact::cli {

// standard input in raw mode (a key at a time, no echo; Ctrl-C still a signal) while this
// lives, when it is a terminal. The terminal's mode comes back on every way out: this
// object's end (a normal exit, an exception, SIGINT / SIGTERM through the stop handlers that
// end the play loop), SIGHUP, SIGQUIT and SIGABRT (restored, then the signal's own action),
// and Ctrl-Z (restored while stopped, raw again on SIGCONT). One at a time per process.
class TerminalKeys {
 public:
  // nothing when not `enabled` (a node of a launched graph leaves the terminal to the launcher)
  explicit TerminalKeys(bool enabled);
  ~TerminalKeys();
  TerminalKeys(const TerminalKeys&) = delete;
  TerminalKeys& operator=(const TerminalKeys&) = delete;

  // standard input is a terminal, now in raw mode
  bool active() const { return active_; }
  // the next key typed, waiting up to timeout_ns (a signal ends the wait); none: nullopt
  std::optional<char> key(std::int64_t timeout_ns);

 private:
  bool active_ = false;
};

class PlayClock {
 public:
  // rate: the speed factor (0: no waiting); keys: may be inactive (no terminal); on_change:
  // called when the clock pauses or resumes (to redraw the progress)
  PlayClock(double rate, TerminalKeys& keys, std::function<void()> on_change);

  // a pass over the recording starts at the message logged at first_log_ns, now
  void restart(std::int64_t first_log_ns);
  // waits until the message logged at log_ns is due: its recorded time scaled by the rate,
  // the time paused left out; while paused, until `s` steps one message (then the timing
  // goes on from there). Answers the keys meanwhile. False when a stop was requested.
  bool wait(std::int64_t log_ns);

  bool paused() const { return paused_; }
  void set_paused(bool paused);

 private:
  // one key typed (within timeout_ns), answered
  void answer_keys(std::int64_t timeout_ns);
  std::int64_t offset_ns(std::int64_t log_ns) const;

  double rate_;
  TerminalKeys& keys_;
  std::function<void()> on_change_;
  std::int64_t first_log_ns_ = 0, wall0_ns_ = 0, paused_at_ns_ = 0;
  bool paused_ = false;
  int steps_ = 0;  // messages asked for with `s` while paused
};

}  // namespace enact::cli
