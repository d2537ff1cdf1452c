#pragma once
// The bridge task of Khatchatourov et al. (2009): the subject must stay on the top surface
// of the bridge from start to end. Fed one sample per model step (time, contact with the
// top surface, progress along the bridge), it counts falls with the 1 s rule in both
// directions and accumulates the trial metrics. update() allocates nothing.
#include <cstdint>

namespace enact::task {

struct TaskParams {
  double min_fall_s = 1.0;        // a loss of contact shorter than this is not a fall
  double min_recovery_s = 1.0;    // contact regained for less than this does not end a fall
  double end_progress = 0.98;     // progress fraction that completes the bridge (while on top)
};

struct Metrics {
  int falls = 0;
  double time_total_s = 0.0;  // trial start to completion (or to the last sample)
  double time_out_s = 0.0;    // cumulated duration of counted falls
  double ratio = 0.0;         // time_out_s / time_total_s (0 when time_total_s is 0)
  bool completed = false;     // end of the bridge reached on top
  double progress = 0.0;      // furthest progress fraction reached on top, [0, 1]
};

enum class TaskEventKind : std::uint8_t { none, fall_start, fall_end, completed };

// an event is reported once it is certain: a fall start is known min_fall_s after the
// contact was lost, so `time_ns` is when it happened, which may lie in the past.
// `completed` also closes a fall still open at that time (no separate fall_end); if a fall
// starts or ends on the very sample that completes the trial, only `completed` is reported
// and the metrics still hold the fall.
struct TaskEvent {
  TaskEventKind kind = TaskEventKind::none;
  std::int64_t time_ns = 0;
};

// Each sample's contact state holds until the next sample: contact lost at t0 and regained
// at t lasted t - t0, so a loss is a fall when t - t0 >= min_fall_s whether the sample at t
// is still off or already back on (and likewise for min_recovery_s). Samples older than the
// last one are ignored.
class BridgeTask {
 public:
  // throws std::invalid_argument on a negative or non-finite duration, or an end_progress
  // outside (0, 1]
  explicit BridgeTask(TaskParams params = {});

  // begin a trial at this time; the subject is taken to start on the top surface
  void reset(std::int64_t start_ns);
  // one sample; at most one event per call (fall_start, fall_end, completed); after
  // completion further samples change nothing
  TaskEvent update(std::int64_t time_ns, bool on_top, double progress);
  // metrics as of the last sample; a fall still open at that time counts up to it
  Metrics metrics() const;
  bool falling() const;  // a counted fall is in progress

  // the trial so far as its task events tell it (times on the task's clock; -1: none): where
  // a recording that starts mid-trial takes the trial up (sim::Keyframe)
  struct Account {
    std::int64_t start_ns = 0;
    int falls = 0;
    std::int64_t closed_out_ns = 0;   // time out of the falls already ended
    std::int64_t fall_since_ns = -1;  // a counted fall still open began here
    std::int64_t end_ns = -1;         // the bridge was completed here
    std::int64_t last_ns = 0;         // the last sample
  };
  Account account() const;

 private:
  enum class Phase : std::uint8_t {
    on_top,        // on the top surface
    pending_off,   // contact lost at lost_ns_, not yet min_fall_s ago
    falling,       // a counted fall that began at lost_ns_
    pending_on,    // in a fall, contact regained at regained_ns_, not yet min_recovery_s ago
  };

  // moves the fall state machine by one sample; returns fall_start / fall_end or none
  TaskEvent advance(std::int64_t time_ns, bool on_top);

  std::int64_t min_fall_ns_ = 0;
  std::int64_t min_recovery_ns_ = 0;
  double end_progress_ = 1.0;

  Phase phase_ = Phase::on_top;
  std::int64_t start_ns_ = 0;
  std::int64_t last_ns_ = 0;         // time of the last sample (start_ns_ before any)
  std::int64_t lost_ns_ = 0;         // contact lost (start of a pending or counted fall)
  std::int64_t regained_ns_ = 0;     // contact regained inside a counted fall
  std::int64_t closed_out_ns_ = 0;   // time out of the falls already ended
  std::int64_t completed_ns_ = 0;
  int falls_ = 0;
  bool completed_ = false;
  double progress_ = 0.0;
};

}  // namespace enact::task
