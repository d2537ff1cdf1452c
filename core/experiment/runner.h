#pragma once
// The experiment runner: every trial of the plan in a real graph started from the
// experiment's trial launch file (the same nodes and supervisor as `enact launch`), with a
// logger node recording the trial to its own MCAP file from the first tick. A trial ends
// when the simulator reports the bridge completed (the runner then stops the graph) or at
// the time limit: the clock master stops itself (the launch file gives it limit_s and
// does not require it; a co-located one says so with a TRIAL_END "stopped" and the runner
// stops the graph then), and in real time the runner stops the rest a second after the
// limit at the latest. The trial graphs run on their launch file's clock, or on
// ExperimentSpec::clock (--clock): in simulated time a recording must hold every tick. Its
// metrics come from the recording (read_trial) and go to results.csv (measured trials) or
// practice.csv as soon as it ends, so an interrupted run resumes where it stopped and never
// runs a completed trial again.
//
// Signals: call launch::block_supervisor_signals() before any thread starts (the bus's
// included); SIGINT / SIGTERM then stop the run after the current trial is abandoned (it
// runs again on resume). The nodes' output (stdout and stderr) goes to each trial's log
// file, so the user interface must write to its own duplicate of the terminal.
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "core/experiment/experiment.h"
#include "core/task/bridge_task.h"

namespace enact::experiment {

// the experimenter's commands during a trial with a person
enum class TrialCommand : std::uint8_t {
  none,
  reset,  // the subject was repositioned at the start (a RESET task event is recorded)
  abort,  // stop this trial now; it is not kept and runs again
};

// where the run is, for the progress display
struct Progress {
  std::size_t done = 0;           // trials of the plan done, earlier runs included
  std::size_t total = 0;
  const Trial* current = nullptr; // the trial running now (null between trials)
  double trial_s = 0.0;           // how long it has run
  double elapsed_s = 0.0;         // this run so far
  double left_s = 0.0;            // estimate of the time left
};

// what the runner asks of the person running it (the command line implements it)
class RunnerUi {
 public:
  virtual ~RunnerUi();
  // with people: before a trial; false stops the run here (it resumes later)
  virtual bool start_trial(const Trial& trial) = 0;
  // with people: polled during a trial, about every 50 ms; never blocks
  virtual TrialCommand poll(const Trial& trial) = 0;
  // with people: after a subject's last measured trial, the rank of each condition label
  // (1 = preferred); an empty map skips the ranking
  virtual std::map<std::string, int> ranking(const std::string& subject, const std::vector<Condition>& conditions) = 0;
  // with people, in a discrimination trial once its intervals are over: 1 or 2 when the
  // person named that interval, 0 while not yet; polled about every 20 ms, never blocks
  virtual int interval_answer() = 0;
  // about once a second, and after each trial
  virtual void progress(const Progress& progress) = 0;
  // a line for the person running the experiment (trial outcomes, problems)
  virtual void note(const std::string& line) = 0;
};

// a pending SIGINT or SIGTERM (blocked by launch::block_supervisor_signals, so they wait),
// taken; true if there was one
bool take_stop_signal();

struct RunSummary {
  std::size_t run = 0;          // trials run now
  std::size_t skipped = 0;      // trials done by an earlier run
  std::size_t failed = 0;       // trials whose graph failed (they run again on resume)
  bool interrupted = false;     // stopped before the end (signal, or the experimenter)
  std::string results;          // results.csv
};

// every node of the trial graphs checks its parameters (launch::check_nodes), once per
// condition and kind of trial, with the arguments the trial would get (recordings into
// `out`); the problems found, empty when every trial graph would start
std::vector<std::string> check_trial_graphs(const ExperimentSpec& spec, const std::vector<Trial>& plan, const std::string& out);

// runs the plan of `spec` into the folder `out` (created): results.csv, practice.csv,
// ranking.csv (people), plan.csv, trials/<stem>.mcap and .log. A folder holding an earlier
// run of the same plan resumes it; one holding another plan is refused (config::Error).
RunSummary run_experiment(const ExperimentSpec& spec, const std::string& out, RunnerUi& ui);

}  // namespace enact::experiment
