#pragma once
// An experiment file (YAML, docs/experiments.md) and the plan of trials it makes: which
// subject does which condition in which order, with optional familiarisation and practice
// trials. The plan is a pure function of the file (and its seed): a resumed run makes the
// same plan and skips the trials already done.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/rt/clock.h"

namespace enact::experiment {

enum class Order : std::uint8_t {
  random,    // a seeded random permutation of the conditions per subject
  balanced,  // rows of a balanced Latin square (Williams 1949), subject i on row i
};

enum class TrialKind : std::uint8_t { familiarisation, practice, measured };
const char* to_string(TrialKind kind);

// a condition: the label in results.csv and what the simulator's `model` param gets
struct Condition {
  std::string label;  // the preset's name, or the model file's `name`
  std::string model;  // the preset's name, or the model file's absolute path
};

struct ExperimentSpec {
  std::string file;                 // the experiment file (absolute)
  std::string name;
  std::uint64_t seed = 1;
  std::vector<std::string> subjects;  // ids, in order
  std::string virtual_subject;      // a virtual subject's file (absolute); "" = people
  std::vector<Condition> conditions;
  Order order = Order::random;
  double limit_s = 180.0;           // a measured trial stops here
  double familiarisation_s = 0.0;   // 0: no familiarisation trial
  double practice_s = 0.0;          // 0: no practice trial before each condition
  std::string launch;               // the trial's launch file (absolute)
  std::vector<std::pair<std::string, std::string>> launch_args;  // more --arg NAME=VALUE for it
  std::optional<rt::GraphClock> clock;  // --clock: the trial graphs' clock over their launch file's

  bool virtual_subjects() const { return !virtual_subject.empty(); }
};

// read an experiment file; paths in it are relative to it. Throws config::Error with
// file:line and the fix (unknown keys, bad values, conditions that are neither a preset nor
// a computer-model file, a missing subject or launch file).
ExperimentSpec load_experiment(const std::string& path);

// --subjects N (ids 1..N) and --conditions A,B,... on top of the file; throws config::Error
std::vector<std::string> subjects_numbered(int count);
void override_subjects(ExperimentSpec& spec, int count);
void override_conditions(ExperimentSpec& spec, const std::vector<std::string>& conditions);
// the trial graph's launch arguments the runner sets for each trial (model, recording, ...)
const std::vector<std::string>& runner_launch_args();
// --arg NAME=VALUE over the file's launch_args: NAME must be an argument the trial graph
// declares and not one the runner sets (model, recording, ...); throws config::Error
void override_launch_args(ExperimentSpec& spec, const std::vector<std::pair<std::string, std::string>>& args);

// one trial of the plan
struct Trial {
  std::size_t index = 0;       // position in the plan, from 0
  std::string subject;
  std::size_t subject_index = 0;
  Condition condition;
  int order = 0;               // position of the condition in the subject's order, from 1
  TrialKind kind = TrialKind::measured;
  double limit_s = 0.0;
  std::uint32_t subject_seed = 0;  // the virtual subject's traits (the same for all its trials)
  std::uint32_t noise_seed = 0;    // its noise in this trial
  std::string file_stem;       // e.g. "s01_CM2_measured": the trial's recording and log
};

// every trial, subject after subject: [familiarisation], then per condition in the
// subject's order [practice] and the measured trial
std::vector<Trial> make_plan(const ExperimentSpec& spec);

// the order (indices into conditions) of `count` conditions for subject `subject_index`
std::vector<std::size_t> condition_order(Order order, std::size_t count, std::size_t subject_index, std::uint64_t seed);

}  // namespace enact::experiment
