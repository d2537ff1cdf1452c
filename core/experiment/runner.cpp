#include "core/experiment/runner.h"

#include <signal.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include "core/bus/typed.h"
#include "core/config/format.h"
#include "core/config/yaml.h"
#include "core/experiment/results.h"
#include "core/experiment/trial_graph.h"
#include "core/graph/topics.h"
#include "core/params/node_params.h"
#include "core/launch/launch_file.h"
#include "core/rt/clock.h"
#include "msgs/task_event.pb.h"

namespace enact::experiment {
namespace {

namespace fs = std::filesystem;

// (kDrain_s: trial_graph.h)
constexpr std::int64_t kDrainNs = static_cast<std::int64_t>(kDrain_s * 1e9);
// a trial that reached its limit but for this long is taken as stopped by it: a loaded
// machine can stall the loop for tens of ms, and the clock master skips the ticks it missed
constexpr double kLimitSlack_s = 0.5;

// the launch arguments of a trial's graph
std::map<std::string, std::string> trial_arguments(const ExperimentSpec& spec, const Trial& trial, const std::string& recording) {
  std::map<std::string, std::string> a(spec.launch_args.begin(), spec.launch_args.end());
  a["model"] = trial.condition.model;
  a["recording"] = recording;
  a["limit_s"] = config::number(trial.limit_s);
  if (spec.virtual_subjects()) {
    a["subject"] = spec.virtual_subject;
    a["subject_seed"] = std::to_string(trial.subject_seed);
    a["noise_seed"] = std::to_string(trial.noise_seed);
  }
  return a;
}

// a trial's graph, from the experiment's trial launch file, on the run's clock
launch::LaunchDescription trial_graph(const ExperimentSpec& spec, const Trial& trial, const std::string& recording) {
  return load_trial_graph(spec.launch, trial_arguments(spec, trial, recording), spec.clock);
}

enum class Outcome : std::uint8_t { done, aborted, interrupted, failed };

struct TrialResult {
  Outcome outcome = Outcome::failed;
  RecordedTrial recorded;
  std::string problem;
};

// the time left: each trial left takes the mean of those run (at most its limit and the
// mean start-up), or its limit before any ran
struct Estimate {
  double run_s = 0.0;
  double overhead_s = 0.0;
  int runs = 0;
  void add(double wall_s, double trial_s) {
    run_s += trial_s;
    overhead_s += std::max(0.0, wall_s - trial_s);
    ++runs;
  }
  double left_s(const std::vector<Trial>& plan, std::size_t from, const std::set<std::string>& done) const {
    double left = 0.0;
    for (std::size_t i = from; i < plan.size(); ++i) {
      if (done.count(trial_key(plan[i].subject, plan[i].condition.label, plan[i].kind))) continue;
      left += runs == 0 ? plan[i].limit_s : std::min(plan[i].limit_s, run_s / runs) + overhead_s / runs;
    }
    return left;
  }
};

class TrialRun {
 public:
  TrialRun(const ExperimentSpec& spec, const Trial& trial, const std::string& folder, RunnerUi& ui, Progress progress)
      : spec_(spec), trial_(trial), ui_(ui), progress_(progress) {
    recording_ = folder + "/" + trial.file_stem + ".mcap";
    log_ = folder + "/" + trial.file_stem + ".log";
  }

  TrialResult run() {
    std::error_code ec;
    fs::remove(recording_, ec);  // an abandoned attempt
    launch::LaunchDescription graph = trial_graph(spec_, trial_, recording_);
    simulated_ = graph.clock == rt::GraphClock::simulated;
    const int code = run_trial_graph(spec_.name + "/" + trial_.subject + "_" + trial_.condition.label, spec_.launch, std::move(graph), log_,
                                     [this](GraphRun& g) { watch(g); });
    return outcome(code);
  }

  double trial_s() const { return trial_s_; }

 private:
  // stop the graph: the supervisor stops it in order
  void stop_graph(GraphRun& g) {
    stop_sent_.store(true);
    g.stop();
  }

  // the runner's side of the trial, while the supervisor runs the graph: announce it, watch
  // for the simulator's end of the trial, take the experimenter's commands, show progress
  void watch(GraphRun& g) {
    bus::Publisher<msgs::TaskEvent> publish(g.out, graph::kTaskEvent);
    bus::ByteSubscriber in;
    bus::Subscriber<msgs::TaskEvent> events(in, graph::kTaskEvent);
    in.connect(g.endpoint);
    msgs::TaskEvent event;
    auto announce = [&](msgs::TaskEvent::Kind kind, const std::string& detail) {
      event.Clear();
      event.set_kind(kind);
      event.set_time_ns(rt::now_ns());
      event.set_condition(trial_.condition.label);
      event.set_subject(trial_.subject);
      event.set_trial(static_cast<std::uint32_t>(trial_.index));
      event.set_detail(detail);
      publish.publish(event);
    };
    const bool person = !spec_.virtual_subjects();
    bool announced = false;
    std::int64_t ended_ns = 0;  // when the trial ended (0: not yet)
    std::int64_t start_ns = rt::now_ns(), shown_ns = start_ns;
    while (!g.finished()) {
      // announced once the attach point forwards task/event from here (this thread's own
      // subscription reached it: so did the logger's, made before the graph was ready)
      if (g.ready() && !announced && g.out.has_subscribers(graph::kTaskEvent)) {
        announced = true;
        start_ns = rt::now_ns();
        announce(msgs::TaskEvent::CONDITION, to_string(trial_.kind));
        announce(msgs::TaskEvent::TRIAL_START, "");
      }
      // the trial's end: the simulator's TRIAL_END, or the clock master gone (its TRIAL_END
      // may come before this thread's subscription reached the attach point: a simulated
      // trial can end that soon). In real time the graph stops at once; in simulated time the
      // loop ran ahead of the logger, which gets the drain time to take what is still on its
      // way before it is stopped
      if (events.receive(event, 20) && event.header().source() != kRunnerNode && event.kind() == msgs::TaskEvent::TRIAL_END && ended_ns == 0) {
        ended_ns = rt::now_ns() - (simulated_ ? 0 : kDrainNs);
      }
      if (ended_ns == 0) ended_ns = g.clean_exit_ns();
      if (ended_ns != 0 && !stop_sent_.load() && rt::now_ns() - ended_ns >= kDrainNs) stop_graph(g);
      if (!announced) continue;
      trial_s_ = seconds_since(start_ns);
      if (person) {
        const TrialCommand command = ui_.poll(trial_);
        if (command == TrialCommand::reset) announce(msgs::TaskEvent::RESET, "the experimenter repositioned the subject at the start");
        if (command == TrialCommand::abort) {
          aborted_ = true;
          stop_graph(g);
        }
      }
      // the clock master ends the trial at its limit; in real time a stalled one is stopped
      if (!simulated_ && trial_s_ > trial_.limit_s + kDrain_s) stop_graph(g);
      if (seconds_since(shown_ns) >= 1.0) {
        shown_ns = rt::now_ns();
        progress_.current = &trial_;
        progress_.trial_s = trial_s_;
        ui_.progress(progress_);
      }
    }
  }

  TrialResult outcome(int code) const {
    TrialResult r;
    if (aborted_) return {Outcome::aborted, {}, "aborted by the experimenter"};
    if (code == 0 && !stop_sent_) return {Outcome::interrupted, {}, "interrupted"};
    try {
      const RecordedTrial t = read_trial(recording_);
      if (t.first_state_seq != 1) {
        return {Outcome::failed, {}, "the recording misses the trial's start (first device state seq " + std::to_string(t.first_state_seq) + "; see " + log_ + ")"};
      }
      if (!t.metrics.completed && t.duration_s < trial_.limit_s - kLimitSlack_s) {
        return {Outcome::failed, {}, "the graph stopped at " + config::number(t.duration_s) + " s of " + config::number(trial_.limit_s) + " s (see " + log_ + ")"};
      }
      // simulated time waits for every observer: a gap is a fault, not the machine's speed
      if (simulated_ && t.state_gaps > 0) {
        return {Outcome::failed, {}, "the recording misses " + std::to_string(t.state_gaps) + " device states in simulated time (see " + log_ + ")"};
      }
      r.outcome = Outcome::done;
      r.recorded = t;
    } catch (const std::exception& e) {
      const std::string error = first_error(log_);
      r.problem = error.empty() ? std::string("no usable recording: ") + e.what() + " (see " + log_ + ")" : "the graph failed: " + error + " (see " + log_ + ")";
    }
    return r;
  }

  // the first line of a log that reports an error, "" when none does
  static std::string first_error(const std::string& log) {
    std::ifstream in(log);
    std::string line;
    while (std::getline(in, line)) {
      if (line.find("error") != std::string::npos) return line;
    }
    return "";
  }

  const ExperimentSpec& spec_;
  const Trial& trial_;
  RunnerUi& ui_;
  Progress progress_;
  std::string recording_, log_;
  std::atomic<bool> stop_sent_{false};
  std::atomic<bool> aborted_{false};
  bool simulated_ = false;  // the trial graph's clock
  std::atomic<double> trial_s_{0.0};
};

}  // namespace

RunnerUi::~RunnerUi() = default;

bool take_stop_signal() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  const timespec zero{0, 0};
  return sigtimedwait(&set, nullptr, &zero) > 0;
}

std::vector<std::string> check_trial_graphs(const ExperimentSpec& spec, const std::vector<Trial>& plan, const std::string& out) {
  std::vector<std::string> problems;
  std::set<std::string> checked;
  for (const Trial& t : plan) {
    if (!checked.insert(t.condition.label + "/" + to_string(t.kind)).second) continue;
    const launch::LaunchDescription graph = trial_graph(spec, t, out + "/trials/" + t.file_stem + ".mcap");
    for (const std::string& p : graph::check_graph(graph)) problems.push_back("condition " + t.condition.label + ": " + p);
  }
  return problems;
}

namespace {

// a measured or practice trial done, in one line for the person running the experiment
std::string trial_line(const Trial& t, const RecordedTrial& recorded) {
  char task[96];
  if (recorded.task) {
    std::snprintf(task, sizeof task, "falls %d, time %.2f s, time out %.2f s%s", recorded.metrics.falls, recorded.metrics.time_total_s,
                  recorded.metrics.time_out_s, recorded.metrics.completed ? "" : ", not completed");
  } else {
    std::snprintf(task, sizeof task, "time %.2f s (no task in this scene: no falls or completion to count)", recorded.metrics.time_total_s);
  }
  char line[320];
  std::snprintf(line, sizeof line, "subject %s, %s (%s %d): %s%s", t.subject.c_str(), t.condition.label.c_str(), to_string(t.kind), t.order, task,
                recorded.missed_deadlines ? (", " + std::to_string(recorded.missed_deadlines) + " deadlines missed").c_str() : "");
  return line;
}

// with people: once every trial of `subject` is done, the ranking of the conditions, asked and
// appended to `ranking`
void ask_ranking(const ExperimentSpec& spec, const std::vector<Trial>& plan, const std::string& subject, const std::set<std::string>& done, RunnerUi& ui,
                 const std::string& ranking) {
  bool all_done = true;
  for (const Trial& other : plan) all_done = all_done && (other.subject != subject || done.count(trial_key(other.subject, other.condition.label, other.kind)));
  const std::map<std::string, int> ranks = all_done ? ui.ranking(subject, spec.conditions) : std::map<std::string, int>{};
  if (!ranks.empty()) append_ranking(ranking, subject, ranks);
}

}  // namespace

RunSummary run_experiment(const ExperimentSpec& spec, const std::string& out, RunnerUi& ui) {
  fs::create_directories(out + "/trials");
  const std::vector<Trial> plan = make_plan(spec);
  // plan.csv: written by the first run, the same for every resumed one
  keep_or_check(out + "/plan.csv", plan_text(plan), "experiment file, --subjects or --conditions differ");
  // one clock per folder: a resumed run on another clock would mix them in results.csv
  if (!plan.empty()) keep_or_check(out + "/clock.txt", std::string(rt::to_string(trial_graph(spec, plan.front(), "").clock)) + "\n", "--clock differs");
  std::error_code ec;
  fs::copy_file(spec.file, out + "/experiment.yaml", fs::copy_options::skip_existing, ec);
  RunSummary summary;
  summary.results = out + "/results.csv";
  const std::string practice = out + "/practice.csv", ranking = out + "/ranking.csv";
  std::set<std::string> done = done_trials(summary.results);
  for (const std::string& key : done_trials(practice)) done.insert(key);
  const std::set<std::string> ranked = ranked_subjects(ranking);
  const bool person = !spec.virtual_subjects();

  const std::int64_t start_ns = rt::now_ns();
  Estimate estimate;
  Progress progress;
  progress.total = plan.size();
  int failures = 0;
  for (std::size_t i = 0; i < plan.size() && !summary.interrupted; ++i) {
    const Trial& t = plan[i];
    progress.done = i;
    progress.current = nullptr;
    progress.elapsed_s = seconds_since(start_ns);
    progress.left_s = estimate.left_s(plan, i, done);
    if (done.count(trial_key(t.subject, t.condition.label, t.kind))) {
      ++summary.skipped;
      continue;
    }
    // a trial: with a person, the experimenter starts it (again after an abort)
    Outcome outcome = Outcome::aborted;
    while (outcome == Outcome::aborted) {
      if (take_stop_signal() || (person && !ui.start_trial(t))) {
        summary.interrupted = true;
        break;
      }
      ui.progress(progress);
      const std::int64_t began_ns = rt::now_ns();
      TrialRun run(spec, t, out + "/trials", ui, progress);
      const TrialResult r = run.run();
      outcome = r.outcome;
      if (outcome == Outcome::done) {
        append_result(t.kind == TrialKind::measured ? summary.results : practice, t, r.recorded);
        done.insert(trial_key(t.subject, t.condition.label, t.kind));
        estimate.add(seconds_since(began_ns), run.trial_s());
        ++summary.run;
        failures = 0;
        ui.note(trial_line(t, r.recorded));
      } else if (outcome == Outcome::interrupted) {
        summary.interrupted = true;
      } else {
        ui.note("subject " + t.subject + ", " + t.condition.label + " (" + to_string(t.kind) + "): " + r.problem +
                (outcome == Outcome::aborted ? "; it runs again" : "; it runs again on resume"));
        if (outcome == Outcome::failed) {
          ++summary.failed;
          if (++failures >= kMaxFailures) {
            ui.note("stopping: " + std::to_string(failures) + " trials failed in a row");
            summary.interrupted = true;
          }
        }
        if (!person) break;
      }
    }
    // with people: the ranking of the conditions after a subject's last measured trial
    const bool last_of_subject = i + 1 == plan.size() || plan[i + 1].subject != t.subject;
    if (person && last_of_subject && !summary.interrupted && !ranked.count(t.subject)) ask_ranking(spec, plan, t.subject, done, ui, ranking);
  }
  progress.done = 0;
  for (const Trial& t : plan) progress.done += done.count(trial_key(t.subject, t.condition.label, t.kind));
  progress.current = nullptr;
  progress.elapsed_s = seconds_since(start_ns);
  progress.left_s = estimate.left_s(plan, 0, done);
  ui.progress(progress);
  return summary;
}

}  // namespace enact::experiment
