// enact experiment FILE: run an experiment's trials (virtual subjects or people), each in
// its own graph, recorded, into results.csv; resumable.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "core/config/format.h"
#include "core/config/share.h"
#include "core/config/yaml.h"
#include "core/experiment/discrimination.h"
#include "core/experiment/experiment.h"
#include "core/experiment/runner.h"
#include "core/launch/supervisor.h"
#include "core/math/random.h"
#include "core/rt/clock.h"
#include "nodes/enact/child_process.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kExperimentHelp = R"help(usage: enact experiment FILE [--subjects N] [--conditions A,B,...] [--out DIR] [--clock real|simulated] [--plan]
                        [--seed S] [--arg NAME=VALUE]... [--replicates N [--jobs J]]

Run the experiment of FILE (format: docs/experiments.md): every subject through every
condition in a seeded random or balanced order, with optional familiarisation and practice
trials. Each trial runs in its own graph, started from the experiment's trial launch file
(co-located or distributed: the same nodes as `enact launch`), and is recorded to
DIR/trials/<subject>_<condition>_<kind>.mcap by a logger node (the nodes' output goes to the
.log beside it). A trial ends when the bridge is completed or at the time limit; its metrics
go to DIR/results.csv (subject,condition,order,falls,time_total_s,time_out_s,ratio,
completed,missed_deadlines) at once. Run again with the same FILE and DIR to resume: completed trials never
run again.

Virtual subjects (virtual_subject: in FILE) hold simulated devices and run unattended.
With people (no virtual_subject), the experimenter is asked before each trial (Enter:
start, q: stop here and resume later); during a trial, r + Enter records that the subject
was put back at the start, a + Enter aborts the trial (it runs again); after a subject's
last trial the subject's ranking of the conditions is asked (DIR/ranking.csv).

Then: /usr/bin/python3 "$(enact share scripts/analyze.py)" DIR/results.csv --out DIR/analysis

A file with `kind: discrimination` (docs/experiments.md, "Discrimination experiments") runs two-interval
discrimination trials about a live parameter (e.g. stiffness_n_per_m) under constant
stimuli, staircases or QUEST. Each trial runs in its own graph (the file's graph), recorded
to DIR/trials/<subject>_<condition>_t<N>.mcap: two intervals, each a live setting of the
parameter explored for interval_s, then the answer, each a task/event in the recording.
Virtual observers answer at once; people (no virtual_observers) are asked before each
condition (Enter: start, q: stop) and answer each trial with 1 or 2 + Enter, or the
device's button 1 or 2. graph: false runs virtual observers without a graph. Results:
DIR/trials.csv (one row per trial, at once, with the response time) and DIR/summary.csv
(per subject and condition: the fitted JND, its profile-likelihood and bootstrap 95 %
intervals, the Weber fraction). Run again to resume.
Then: /usr/bin/python3 "$(enact share scripts/psychophysics.py)" plot DIR/trials.csv --out DIR/figures
  with the fit's options of the analysis: section (the command printed at the end gives them)

options:
  --subjects N          N subjects (ids 1..N) instead of the file's
  --conditions A,B,...  these conditions instead of the file's (presets or model files)
  --out DIR             results folder (default: results/<name of the experiment>)
  --clock CLOCK         the trial graphs' clock, over their launch file's: simulated runs
                        each trial as fast as the machine goes (virtual subjects or
                        observers, simulated devices; the co-located or the distributed
                        graph), the same trial as in real time
                        without a missed deadline; results.csv's missed_deadlines says how
                        many each real-time trial missed
  --plan                print the plan (trial order, seeds), check every trial graph's
                        parameters (as a run does first), and run nothing
  --seed S              the plan's seed instead of the file's (subjects' traits, noise, orders)
  --arg NAME=VALUE      a launch argument of the trial graph over the file's launch_args
                        (repeatable; e.g. --arg rate_hz=1000); `enact sweep` runs a grid of them
  --replicates N        virtual subjects, simulated time: N independent replicates of the whole
                        experiment (replicate k: fresh subjects and noise from a seed derived
                        from the file's and k), into DIR/replicate_001 ... each resumable, J at
                        once (--jobs, default: one per CPU); then scripts/power.py DIR (enact share) gives the
                        virtual baseline's power against the number of subjects
Exit status: 0 every trial done, 1 trials failed (they run again on resume) or an error,
2 bad arguments, 130 stopped before the end (Ctrl-C, or q at a prompt).
)help";

// a SIGINT or SIGTERM waiting (they are blocked for the supervisor), not taken
bool stop_pending() {
  sigset_t pending;
  sigpending(&pending);
  return sigismember(&pending, SIGINT) || sigismember(&pending, SIGTERM);
}

// the terminal side of the runner: a progress bar (a line per trial when not a terminal),
// prompts and the ranking on stdin
class TerminalUi final : public experiment::RunnerUi {
 public:
  explicit TerminalUi(FILE* term) : term_(term), tty_(isatty(fileno(term)) != 0) {}

  bool start_trial(const experiment::Trial& t) override {
    clear();
    std::fprintf(term_, "next: subject %s, condition %s (%s, %d of the subject's order). Enter: start, q: stop here (resume later) > ",
                 t.subject.c_str(), t.condition.label.c_str(), experiment::to_string(t.kind), t.order);
    std::fflush(term_);
    std::string line;
    if (!read_line(line, -1)) return false;
    return line != "q";
  }

  experiment::TrialCommand poll(const experiment::Trial&) override {
    std::string line;
    if (!read_line(line, 0)) return experiment::TrialCommand::none;
    if (line == "r") return experiment::TrialCommand::reset;
    if (line == "a") return experiment::TrialCommand::abort;
    note("commands during a trial: r (the subject was put back at the start), a (abort the trial)");
    return experiment::TrialCommand::none;
  }

  int interval_answer() override {
    std::string line;
    if (!read_line(line, 0)) return 0;
    if (line == "1" || line == "2") return line[0] - '0';
    note("answer 1 or 2 (+ Enter): the interval you name");
    return 0;
  }

  std::map<std::string, int> ranking(const std::string& subject, const std::vector<experiment::Condition>& conditions) override {
    while (true) {
      clear();
      std::string names;
      for (const auto& c : conditions) names += " " + c.label;
      std::fprintf(term_, "subject %s: rank of each condition, 1 = preferred, in this order:%s (Enter alone: skip) > ", subject.c_str(), names.c_str());
      std::fflush(term_);
      std::string line;
      if (!read_line(line, -1) || line.empty()) return {};
      std::stringstream ss(line);
      std::map<std::string, int> ranks;
      std::vector<bool> used(conditions.size() + 1, false);
      int rank = 0;
      for (const auto& c : conditions) {
        if (!(ss >> rank) || rank < 1 || rank > static_cast<int>(conditions.size()) || used[static_cast<std::size_t>(rank)]) break;
        used[static_cast<std::size_t>(rank)] = true;
        ranks[c.label] = rank;
      }
      if (ranks.size() == conditions.size()) return ranks;
      std::fprintf(term_, "give each of 1 to %zu once, e.g. 2 1 4 3\n", conditions.size());
    }
  }

  void progress(const experiment::Progress& p) override {
    constexpr int kWidth = 24;
    const int filled = p.total ? static_cast<int>(kWidth * p.done / p.total) : kWidth;
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::string now = "between trials";
    if (p.current) {
      now = "subject " + p.current->subject + " " + p.current->condition.label + " " + experiment::to_string(p.current->kind) + " " +
            clock_text(p.trial_s);
    }
    char line[256];
    std::snprintf(line, sizeof line, "[%s] %zu/%zu  %s  elapsed %s  left ~%s", bar.c_str(), p.done, p.total, now.c_str(),
                  clock_text(p.elapsed_s).c_str(), clock_text(p.left_s).c_str());
    if (tty_) {
      std::fprintf(term_, "\r\033[K%s", line);
      shown_ = true;
    } else if (p.current && p.current != last_) {
      std::fprintf(term_, "%s\n", line);
    }
    last_ = p.current;
    std::fflush(term_);
  }

  void note(const std::string& text) override {
    clear();
    std::fprintf(term_, "%s\n", text.c_str());
    std::fflush(term_);
  }

 private:
  // a line from stdin within timeout_ms (-1: until one comes, or a stop signal); false on
  // none, end of input or a stop signal
  bool read_line(std::string& line, int timeout_ms) {
    while (true) {
      const std::size_t eol = buffer_.find('\n');
      if (eol != std::string::npos) {
        line = buffer_.substr(0, eol);
        buffer_.erase(0, eol + 1);
        return true;
      }
      if (eof_ || stop_pending()) return false;
      pollfd fd{STDIN_FILENO, POLLIN, 0};
      if (::poll(&fd, 1, timeout_ms < 0 ? 200 : timeout_ms) <= 0) {
        if (timeout_ms >= 0) return false;
        continue;
      }
      char chunk[256];
      const ssize_t n = read(STDIN_FILENO, chunk, sizeof chunk);
      if (n <= 0) {
        eof_ = true;
        if (!buffer_.empty()) buffer_ += '\n';
        continue;
      }
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
  }

  void clear() {
    if (tty_ && shown_) std::fputs("\r\033[K", term_);
    shown_ = false;
  }

  FILE* term_;
  bool tty_;
  bool shown_ = false;
  bool eof_ = false;
  std::string buffer_;
  const experiment::Trial* last_ = nullptr;
};

void print_plan(const experiment::ExperimentSpec& spec, const std::vector<experiment::Trial>& plan) {
  const std::string who = spec.virtual_subjects() ? "virtual subjects " + spec.virtual_subject : "people";
  std::printf("experiment %s: %zu subjects, %zu conditions, %s order, limit %s s, graph %s, %s\n", spec.name.c_str(), spec.subjects.size(),
              spec.conditions.size(), spec.order == experiment::Order::random ? "random" : "balanced", config::number(spec.limit_s).c_str(),
              spec.launch.c_str(), who.c_str());
  std::printf("%-6s %-10s %-12s %-6s %-16s %-10s %s\n", "trial", "subject", "condition", "order", "kind", "limit_s", "recording");
  for (const auto& t : plan) {
    std::printf("%-6zu %-10s %-12s %-6d %-16s %-10s %s.mcap\n", t.index + 1, t.subject.c_str(), t.condition.label.c_str(), t.order,
                experiment::to_string(t.kind), config::number(t.limit_s).c_str(), t.file_stem.c_str());
  }
}

void print_blocks(const experiment::DiscriminationSpec& spec) {
  std::printf("discrimination %s: %zu subjects, %zu conditions, %s %s around %s, %zu procedures interleaved, %s, %s\n", spec.name.c_str(),
              spec.subjects.size(), spec.conditions.size(), spec.order == experiment::Order::random ? "random" : "balanced", spec.parameter.c_str(),
              config::number(spec.reference).c_str(), spec.procedures.size(), spec.virtual_observers ? "virtual observers" : "people",
              spec.on_graph() ? ("each trial in graph " + spec.launch).c_str() : "no graph");
  std::printf("%-10s %-12s %-6s %s\n", "subject", "condition", "order", "observer's JND");
  for (const auto& b : experiment::make_blocks(spec)) {
    std::printf("%-10s %-12s %-6d %s\n", b.subject.c_str(), b.condition.label.c_str(), b.order, config::number(b.observer.function.threshold).c_str());
  }
}

// a discrimination experiment: each trial in its graph (or none, graph: false), answered by
// virtual observers or people
int discrimination_run(const Args& a, FILE* term) {
  experiment::DiscriminationSpec spec = experiment::load_discrimination(a.positional[0]);
  if (a.has("conditions")) throw UsageError("--conditions is for bridge experiments; edit the discrimination file's conditions");
  if (a.has("subjects")) {
    const double n = a.number("subjects", 0.0);
    if (n != static_cast<int>(n)) throw UsageError("--subjects needs a whole number");
    spec.subjects = experiment::subjects_numbered(static_cast<int>(n));
  }
  spec.clock = clock_option(a);
  if (!spec.virtual_observers && spec.clock == rt::GraphClock::simulated) throw UsageError("people explore the intervals in real time: --clock simulated is for virtual observers");
  const std::string out = a.get("out", "results/" + spec.name);
  if (a.flag("plan")) print_blocks(spec);
  // every trial graph's nodes check their parameters before any trial starts
  const std::vector<std::string> problems = experiment::check_discrimination_graphs(spec, out);
  for (const std::string& p : problems) std::fprintf(stderr, "enact experiment: %s\n", p.c_str());
  if (!problems.empty()) throw config::Error(spec.file + ": a trial graph's nodes refuse their parameters (above); nothing ran");
  if (a.flag("plan")) return 0;
  TerminalUi ui(term);
  if (!spec.virtual_observers) ui.note("people: the experimenter starts each subject's condition; after each trial's two intervals the subject answers 1 or 2");
  const experiment::DiscriminationRun r = experiment::run_discrimination(spec, out, ui);
  ui.note(std::to_string(r.trials_run) + " trials run" + (r.blocks_done_before ? ", " + std::to_string(r.blocks_done_before) + " blocks done before" : "") +
          (r.failed ? ", " + std::to_string(r.failed) + " failed" : "") + "; trials: " + r.trials +
          (r.interrupted ? "\nstopped before the end: run the same command again to resume"
                         : "\nsummary: " + r.summary + "\nfigures: /usr/bin/python3 " + config::shipped("scripts/psychophysics.py") + " plot " + r.trials + " --out " + out + "/figures" +
                                 experiment::script_fit_options(spec.fit)));
  if (r.interrupted) return r.failed ? 1 : 130;
  return 0;
}

// replicate k's seed: independent of the file's and of every other replicate's
// (under 10^15: a --seed given as a number reads back exactly)
std::uint64_t replicate_seed(std::uint64_t seed, int k) { return math::derive_seed(seed, 0x5265706c00ULL + static_cast<std::uint64_t>(k)) % 1'000'000'000'000'000ULL; }

// replicate k's folder under `out`: out/replicate_001 ...
std::string replicate_dir(const std::string& out, int k) {
  char dir[32];
  std::snprintf(dir, sizeof dir, "/replicate_%03d", k);
  return out + dir;
}

// `enact experiment FILE --seed S --out DIR [--subjects N] [--conditions ...] --clock
// simulated` in a child process, its output into DIR/run.log
pid_t start_replicate(const Args& a, const std::vector<std::pair<std::string, std::string>>& spec_args, const std::string& file, std::uint64_t seed, const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> args = {"/proc/self/exe", "experiment", file, "--clock", "simulated", "--seed", std::to_string(seed), "--out", dir};
  for (const char* o : {"subjects", "conditions"}) {
    if (a.has(o)) args.insert(args.end(), {std::string("--") + o, a.get(o)});
  }
  for (const auto& [name, value] : spec_args) args.insert(args.end(), {"--arg", name + "=" + value});
  return start_logged(args, dir + "/run.log", false);
}

// --replicates N: the whole experiment N times with fresh seeds, J at once, each resumable in
// its folder; Ctrl-C stops them (each resumes where it stopped)
int replicates_run(const Args& a, const std::vector<std::pair<std::string, std::string>>& given_args, const experiment::ExperimentSpec& spec,
                   const std::string& out) {
  const double n = a.number("replicates", 0.0);
  const double jobs_given = a.number("jobs", static_cast<double>(std::max(1u, std::thread::hardware_concurrency())));
  if (n < 1 || n != static_cast<int>(n) || jobs_given < 1 || jobs_given != static_cast<int>(jobs_given)) throw UsageError("--replicates and --jobs need a whole number >= 1");
  if (!spec.virtual_subjects()) throw UsageError(spec.file + ": replicates need virtual subjects (people cannot be replicated); the file has none");
  if (a.has("clock") && a.get("clock") != "simulated") throw UsageError("replicates run in simulated time: leave out --clock, or give --clock simulated");
  const int count = static_cast<int>(n), jobs = static_cast<int>(jobs_given);
  std::map<pid_t, int> running;
  int next = 1, done = 0, failed = 0;
  const std::int64_t start_ns = rt::now_ns();
  std::fprintf(stderr, "enact experiment: %d replicates of %s (%zu subjects x %zu conditions each), %d at once, into %s/replicate_NNN\n", count, spec.name.c_str(),
               spec.subjects.size(), spec.conditions.size(), jobs, out.c_str());
  bool stopping = false;
  while ((next <= count && !stopping) || !running.empty()) {
    while (!stopping && next <= count && static_cast<int>(running.size()) < jobs) {
      running[start_replicate(a, given_args, spec.file, replicate_seed(spec.seed, next), replicate_dir(out, next))] = next;
      ++next;
    }
    if (!stopping && experiment::take_stop_signal()) {
      stopping = true;
      for (const auto& [pid, k] : running) kill(pid, SIGTERM);
      std::fprintf(stderr, "enact experiment: stopping; the replicates running stop after their trial (run the same command again to resume)\n");
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid <= 0) {
      rt::sleep_until_ns(rt::now_ns() + 100'000'000);
      continue;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    ok ? ++done : ++failed;
    std::fprintf(stderr, "enact experiment: replicate %d %s (%d of %d done, %.0f s)%s\n", it->second, ok ? "done" : "did not finish", done, count,
                 static_cast<double>(rt::now_ns() - start_ns) * 1e-9, ok ? "" : ("; see " + replicate_dir(out, it->second) + "/run.log").c_str());
    running.erase(it);
  }
  if (stopping) return 130;
  std::fprintf(stderr, "enact experiment: %d replicates done%s; power: /usr/bin/python3 %s %s\n", done,
               failed ? (", " + std::to_string(failed) + " did not finish (run again to resume them)").c_str() : "", config::shipped("scripts/power.py").c_str(), out.c_str());
  return failed ? 1 : 0;
}

}  // namespace

int experiment_run(int argc, char** argv) {
  // --arg may repeat: taken out before the generic parser
  std::vector<std::pair<std::string, std::string>> given_args;
  for (const std::string& kv : take_repeated(argc, argv, "--arg")) {
    const std::size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError("--arg needs NAME=VALUE, got '" + kv + "'");
    given_args.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
  }
  const Args a = parse(argc, argv, 2, {"subjects", "conditions", "out", "clock", "seed", "replicates", "jobs"}, {"plan"});
  if (a.flag("help")) {
    std::fputs(kExperimentHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one experiment file");
  // every thread from here on (the bus's included) leaves SIGINT / SIGTERM to the runner
  launch::block_supervisor_signals();
  if (experiment::is_discrimination(a.positional[0])) {
    const std::unique_ptr<FILE, int (*)(FILE*)> term(fdopen(fcntl(STDERR_FILENO, F_DUPFD_CLOEXEC, 3), "w"), &std::fclose);
    if (!term) throw std::runtime_error("cannot duplicate stderr");
    if (!given_args.empty()) throw UsageError("--arg is for bridge experiments' trial graphs");
    return discrimination_run(a, term.get());
  }
  experiment::ExperimentSpec spec = experiment::load_experiment(a.positional[0]);
  experiment::override_launch_args(spec, given_args);
  if (a.has("subjects")) {
    const double n = a.number("subjects", 0.0);
    if (n != static_cast<int>(n)) throw UsageError("--subjects needs a whole number");
    experiment::override_subjects(spec, static_cast<int>(n));
  }
  if (a.has("conditions")) experiment::override_conditions(spec, split_commas(a.get("conditions")));
  if (a.has("seed")) {
    const double seed = a.number("seed", 0.0);
    if (seed < 0 || seed != std::floor(seed) || seed >= 1e15) throw UsageError("--seed needs a whole number from 0 to 10^15");
    spec.seed = static_cast<std::uint64_t>(seed);
  }
  const std::string out = a.get("out", "results/" + spec.name);
  if (a.has("replicates")) return replicates_run(a, given_args, spec, out);
  spec.clock = clock_option(a);
  const std::vector<experiment::Trial> plan = experiment::make_plan(spec);
  if (a.flag("plan")) print_plan(spec, plan);
  // every trial graph's nodes check their parameters before any trial starts
  const std::vector<std::string> problems = experiment::check_trial_graphs(spec, plan, out);
  for (const std::string& p : problems) std::fprintf(stderr, "enact experiment: %s\n", p.c_str());
  if (!problems.empty()) throw config::Error(spec.file + ": a trial graph's nodes refuse their parameters (above); nothing ran");
  if (a.flag("plan")) return 0;
  // the terminal, kept apart from stderr (which each trial's graph writes to its log)
  FILE* term = fdopen(fcntl(STDERR_FILENO, F_DUPFD_CLOEXEC, 3), "w");
  if (!term) throw std::runtime_error("cannot duplicate stderr");
  TerminalUi ui(term);
  ui.note("experiment " + spec.name + ": " + std::to_string(plan.size()) + " trials (" + std::to_string(spec.subjects.size()) + " subjects x " +
          std::to_string(spec.conditions.size()) + " conditions" + (plan.size() > spec.subjects.size() * spec.conditions.size() ? ", with practice" : "") +
          ") into " + out + (spec.virtual_subjects() ? ", virtual subjects" : ", people: the experimenter starts each trial"));
  const experiment::RunSummary s = experiment::run_experiment(spec, out, ui);
  ui.note(std::to_string(s.run) + " trials run" + (s.skipped ? ", " + std::to_string(s.skipped) + " done before" : "") +
          (s.failed ? ", " + std::to_string(s.failed) + " failed" : "") + "; results: " + s.results +
          (s.interrupted ? "\nstopped before the end: run the same command again to resume" : "\nanalysis: /usr/bin/python3 " + config::shipped("scripts/analyze.py") + " " + s.results + " --out " + out + "/analysis"));
  std::fclose(term);
  if (s.interrupted) return 130;
  return s.failed ? 1 : 0;
}

}  // namespace enact::cli
