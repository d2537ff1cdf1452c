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
// The answers come from virtual observers (a psychometric function per subject and
// condition, core/psychophysics/observer.h). People at the device are not supported yet:
// the file is refused with the fix.
#include <cstdint>
#include <map>
#include <string>
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
  VirtualObservers observers;
  psychophysics::FitSettings fit;
  int bootstrap_replicates = 200;
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

// the interleaved procedures of a block, in their first state
psychophysics::Interleaved make_procedures(const DiscriminationSpec& spec, const DiscriminationBlock& block);

struct DiscriminationRun {
  std::size_t trials_run = 0;
  std::size_t blocks_done_before = 0;
  bool interrupted = false;
  std::string trials;   // trials.csv
  std::string summary;  // summary.csv
};

// trials.csv's header
extern const char* const kDiscriminationTrialsHeader;
// summary.csv's header
extern const char* const kDiscriminationSummaryHeader;

// runs every block into `out` (created): manifest.txt (before the first trial: the file's
// FNV-1a hash, seeds, procedures, analysis and every block with its observer; a run of
// another plan is refused) and experiment.yaml (the file as run), trials.csv (appended per
// trial), summary.csv (written at the end). Stops
// between two trials on SIGINT / SIGTERM (take_stop_signal) or after `max_trials` trials
// (0: no limit) when given, and resumes from trials.csv when run again.
DiscriminationRun run_discrimination(const DiscriminationSpec& spec, const std::string& out, RunnerUi& ui, std::size_t max_trials = 0);

}  // namespace enact::experiment
