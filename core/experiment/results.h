#pragma once
// A trial's results: its metrics as the live simulator reported them in the trial's
// recording, and the experiment's CSV files (results.csv for measured trials, practice.csv
// for familiarisation and practice, ranking.csv for the subjective ranking).
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/experiment/experiment.h"
#include "core/task/bridge_task.h"

namespace enact::experiment {

// what a trial's recording says
struct RecordedTrial {
  task::Metrics metrics;           // from the simulator's task events (progress is not kept)
  std::uint64_t states = 0;        // ffd/state messages
  std::uint64_t first_state_seq = 0;  // 1 when the recording holds the graph's first tick
  std::uint64_t state_gaps = 0;    // device states missing between the first and the last
  double duration_s = 0.0;         // from the first device state to the last
  std::uint64_t missed_deadlines = 0;  // the loop's, as its last node/status said (0 in simulated time)
  bool task = true;                // the recorded scene has a task (falls and completion count)
};

// the metrics of a trial from its recording: time 0 is the first device state (the
// simulator's time 0); falls and their time out from the simulator's FALL_START and
// FALL_END events (the times a fall began and ended), the end from its TRIAL_END (the
// bridge completed) or the last device state (the limit). An independent path from
// `enact metrics`, which replays the device states through a simulator. Throws
// record::Error for a file that is not a recording, config::Error when it holds no device
// state. With `keyframe_stamp_ns` (a recording started on a running graph: its replay's
// keyframe, graph::ReplayStart), the trial is taken up from the simulator's keyframe of that
// stamp (the trial so far: its start, falls, time out) and its events after it.
RecordedTrial read_trial(const std::string& mcap_path, std::int64_t keyframe_stamp_ns = 0);

// results.csv and practice.csv: a header, then one row per trial (numbers at 9 digits)
extern const char* const kResultsHeader;  // subject,condition,order,falls,time_total_s,time_out_s,ratio,completed,missed_deadlines
extern const char* const kPracticeHeader; // the same and kind
// appends a trial's row (the file and its header are created when missing), flushed
void append_result(const std::string& path, const Trial& trial, const RecordedTrial& recorded);
// the trials already in a results.csv or practice.csv, as (subject, condition label, kind)
// keys; an absent file holds none. Throws config::Error (file:line) for a damaged file.
std::set<std::string> done_trials(const std::string& path);
// the key of a trial in done_trials()
std::string trial_key(const std::string& subject, const std::string& condition, TrialKind kind);

// ranking.csv: subject,condition,rank (1 = preferred)
void append_ranking(const std::string& path, const std::string& subject, const std::map<std::string, int>& ranks);
// the subjects already ranked
std::set<std::string> ranked_subjects(const std::string& path);

// the cells of one CSV line (no quoting: enact writes none)
std::vector<std::string> cells(const std::string& line);
// appends one line to a CSV file, writing the header first into a new (or empty) file,
// flushed; throws config::Error when it cannot
void append_line(const std::string& path, const char* header, const std::string& line);

// a run's plan in its folder: `text` written to `path` when it is not there yet; when it is,
// a different text is refused (config::Error: "this folder holds a run of another plan
// (`differs`)" and the fix: the same file and options, or another --out)
void keep_or_check(const std::string& path, const std::string& text, const std::string& differs);

// plan.csv: the whole plan, written when a run starts; a resumed run must make the same one
std::string plan_text(const std::vector<Trial>& plan);

}  // namespace enact::experiment
