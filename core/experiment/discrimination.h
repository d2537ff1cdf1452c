#pragma once
// A discrimination experiment (docs/experiments.md, "Discrimination experiments"): every subject,
// in every condition (computer model), answers two-interval trials "which interval was
// larger?" about a live parameter of the simulator (e.g. stiffness_n_per_m): one interval at
// the reference, the other at reference + level, the reference's interval drawn at random
// and recorded. The levels come from one or more procedures interleaved per subject and
// condition (core/psychophysics: constant stimuli, staircases, QUEST). Every trial goes to
// trials.csv at once; a run resumes from it (the procedures replay their answers) and
// refuses a folder of another experiment. Thresholds are fitted per subject and condition
// (maximum likelihood, profile-likelihood and bootstrap intervals) into summary.csv.
//
// Each trial runs in a graph of its own (the file's `graph`, e.g. trial_rt.yaml), recorded by
// its logger: two intervals, each a live setting of the parameter sent on param/set as
// `enact param set` does (so the simulator's no-jolt rules switch it between two ticks), each
// explored for interval_s of the graph's clock, then the answer; every interval's start and
// end and the answer are task/event messages in the recording. Whoever answers does it
// through one AnswerSource: a virtual observer (virtual_observers: in the file, a
// psychometric function per subject and condition, core/psychophysics/observer.h), or a
// person at the keyboard or the device's buttons (no virtual_observers). `graph: false`
// runs virtual observers without a graph (the fast path: no device, no recording).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/experiment/experiment.h"
#include "core/experiment/runner.h"
#include "core/psychophysics/fit.h"
#include "core/psychophysics/observer.h"
#include "core/psychophysics/procedure.h"

namespace enact::experiment {

// one procedure of the interleaved set: kind and settings (levels in the parameter's unit)
struct ProcedureSpec {
  std::string label;  // e.g. "quest", "staircase_1", unique per experiment
  enum class Kind : std::uint8_t { constant, staircase, quest } kind = Kind::quest;
  psychophysics::ConstantStimuliSettings constant;
  psychophysics::StaircaseSettings staircase;
  psychophysics::QuestSettings quest;
};

// the virtual observers: subject i's Weber fraction in condition c is
// weber_fraction[c] * exp(weber_sd_log * z_i), z_i standard normal from the subject's stream
// (the same z in every condition: a paired design); a Weibull of `exponent` with `lapse`
struct VirtualObservers {
  std::map<std::string, double> weber_fraction;  // by condition label (the file: one number,
                                                 // or a list in the conditions' order)
  double weber_sd_log = 0.2;
  double exponent = 3.5;
  double lapse = 0.02;
};

struct DiscriminationSpec {
  std::string file;  // absolute
  std::string name;
  std::uint64_t seed = 1;
  std::vector<std::string> subjects;
  std::vector<Condition> conditions;
  Order order = Order::random;
  std::string parameter;        // a numeric live parameter of the simulator
  double reference = 0.0;       // its reference value, in its unit
  std::vector<ProcedureSpec> procedures;
  bool virtual_observers = false;  // answered by virtual observers (else by people)
  VirtualObservers observers;
  psychophysics::FitSettings fit;
  int bootstrap_replicates = 200;
  // the trials' graph: its launch file (absolute; "" with graph: false, the fast path) and
  // more --arg NAME=VALUE for it
  std::string launch;
  std::vector<std::pair<std::string, std::string>> launch_args;
  std::optional<rt::GraphClock> clock;  // --clock: over the launch file's
  double interval_s = 2.0;              // each interval lasts this long on the graph's clock
  double answer_limit_s = 60.0;         // a trial not answered this long after its intervals runs again

  bool on_graph() const { return !launch.empty(); }
};

// true when the file's `kind` is discrimination (false for bridge experiments)
bool is_discrimination(const std::string& path);

// reads a discrimination experiment; throws config::Error with file:line and the fix
DiscriminationSpec load_discrimination(const std::string& path);

// one subject in one condition: the procedures' settings (seeded from the experiment, the
// subject and the condition), the observer, and the position in the subject's order
struct DiscriminationBlock {
  std::string subject;
  std::size_t subject_index = 0;
  Condition condition;
  std::size_t condition_index = 0;
  int order = 0;  // from 1
  std::uint64_t seed = 0;
  psychophysics::VirtualObserver observer;
};

// every block, subject after subject, conditions in the subject's order
std::vector<DiscriminationBlock> make_blocks(const DiscriminationSpec& spec);

// one trial as presented: the comparison's level and the reference's interval
struct Presentation {
  const DiscriminationBlock* block = nullptr;
  std::size_t trial = 0;         // within the block, from 0
  std::string procedure;         // its label
  double level = 0.0;            // the comparison is reference + level
  int reference_interval = 1;    // 1 or 2: drawn per trial from the block's seed
  int larger_interval() const { return 3 - reference_interval; }
};

// who answers a trial once its intervals are over, the one way for everyone
class AnswerSource {
 public:
  virtual ~AnswerSource();
  // the interval named (1 or 2), 0 while none is; `buttons`: the device's buttons now
  // (DeviceState.buttons; 0 without a graph). Polled, never blocks.
  virtual int answer(const Presentation& trial, std::uint32_t buttons) = 0;
};

// a block's virtual observer: answers at once, from its psychometric function at the level
// (its draw seeded by the trial's index: a rerun answers alike)
class ObserverAnswers final : public AnswerSource {
 public:
  int answer(const Presentation& trial, std::uint32_t buttons) override;
};

// a person: "1" or "2" at the runner's user interface (RunnerUi::interval_answer), or a
// device button pressed (button 0: interval 1, button 1: interval 2)
class PersonAnswers final : public AnswerSource {
 public:
  explicit PersonAnswers(RunnerUi& ui) : ui_(ui) {}
  int answer(const Presentation& trial, std::uint32_t buttons) override;

 private:
  RunnerUi& ui_;
  std::uint32_t last_buttons_ = ~0u;  // none pressed before the first poll counts
};

// every trial graph's nodes check their parameters (graph::check_graph), once per
// condition, with the arguments a trial gets; the problems found (none without a graph)
std::vector<std::string> check_discrimination_graphs(const DiscriminationSpec& spec, const std::string& out);

// the interleaved procedures of a block, in their first state
// the options of scripts/psychophysics.py (fit, plot) that fit as summary.csv does: e.g.
// " --shape weibull --exponent 3.5 --max-lapse 0.06"
std::string script_fit_options(const psychophysics::FitSettings& fit);

// fewer answers in a block than this and its fit is warned about: with 30 two-interval
// answers the 95 % interval of a proportion correct near the JND's 75 % is already +-0.155
// (1.96 sqrt(0.75 x 0.25 / 30)), as wide as the step from 75 % to 90 % correct, so fewer
// cannot place the threshold; psychophysical fits are small-sample problems even at 120 and
// more trials (Wichmann & Hill 2001, Perception & Psychophysics 63(8):1293-1313)
inline constexpr int kMinTrialsForFit = 30;

// a summary.csv lapse is given to this precision (the fit's lapse bound 0 prints 0, not 1e-15)
inline constexpr double kLapsePrecision = 1e-6;

psychophysics::Interleaved make_procedures(const DiscriminationSpec& spec, const DiscriminationBlock& block);

struct DiscriminationRun {
  std::size_t trials_run = 0;
  std::size_t blocks_done_before = 0;
  std::size_t failed = 0;  // trials whose graph failed (they run again)
  bool interrupted = false;
  std::string trials;   // trials.csv
  std::string summary;  // summary.csv
};

// trials.csv's header (response_time_s: on the graph's clock from the end of the last
// interval to the answer; nan without a graph)
extern const char* const kDiscriminationTrialsHeader;
// summary.csv's header
extern const char* const kDiscriminationSummaryHeader;

// runs every block into `out` (created), each trial in its graph (trials/<stem>.mcap and .log)
// unless graph: false: manifest.txt (before the first trial: the file's
// FNV-1a hash, seeds, procedures, analysis and every block with its observer; a run of
// another plan is refused) and experiment.yaml (the file as run), trials.csv (appended per
// trial), summary.csv (written at the end). Stops
// between two trials on SIGINT / SIGTERM (take_stop_signal), after `max_trials` trials
// (0: no limit) when given, when a person's block is not started (RunnerUi::start_trial) or
// after 3 failed trials in a row (they run again), and resumes from trials.csv when run again.
DiscriminationRun run_discrimination(const DiscriminationSpec& spec, const std::string& out, RunnerUi& ui, std::size_t max_trials = 0);

}  // namespace enact::experiment
