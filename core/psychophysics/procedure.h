#pragma once
// Procedures of a discrimination experiment behind one interface, as PsychoPy's
// TrialHandler, StairHandler and QuestHandler share one (psychopy.org, "psychopy.data"): ask
// for the next level, tell it the answer, ask whether it is finished. A level is the
// difference between the comparison and the reference, in the compared parameter's unit.
//
// Every procedure is a pure function of its settings and the answers it was told: its state
// is that history, serialised by save() and replayed by restore(), which also refuses a
// history the settings would not have produced (another plan). Randomness (the order of
// constant stimuli, which interleaved procedure goes next) is drawn from streams derived
// from a seed and the trial's index, never from a running generator.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace enact::psychophysics {

struct Response {
  double level = 0.0;
  bool correct = false;
};

class Procedure {
 public:
  virtual ~Procedure();
  // the level of the next trial (meaningful while !finished())
  virtual double next_level() const = 0;
  virtual bool finished() const = 0;
  // the procedure's own threshold estimate (staircase: mean of the last reversals; QUEST:
  // the posterior mean; constant stimuli: none, NaN); the analysis fits all trials instead
  virtual double estimate() const = 0;
  // the answer to the trial at next_level()
  void tell(bool correct);

  const std::vector<Response>& history() const { return history_; }
  // the history as text, one "level correct" line per trial (levels to 17 digits)
  std::string save() const;
  // back to no trials, then the saved history told again; throws std::invalid_argument when
  // a saved level is not the one this procedure asks for at that trial
  void restore(const std::string& saved);

 protected:
  virtual void update(double level, bool correct) = 0;
  virtual void reset() = 0;

 private:
  std::vector<Response> history_;
};

// method of constant stimuli: each level `repetitions` times, in blocks that each present
// every level once in a seeded random order
struct ConstantStimuliSettings {
  std::vector<double> levels;
  int repetitions = 10;
  std::uint64_t seed = 1;
};

enum class StepType : std::uint8_t {
  linear,  // level +- step
  log10,   // level * 10^(+-step)
};

// a transformed up-down staircase (Levitt 1971, "Transformed up-down methods in
// psychoacoustics", JASA 49(2B)): `down` correct answers in a row lower the level, `up`
// wrong ones raise it; 1-up-2-down converges on 70.7 % correct (p^2 = 0.5), 1-up-3-down on
// 79.4 % (p^3 = 0.5). Step sizes change at reversals (step_sizes[i] after i reversals, the
// last kept), as PsychoPy's StairHandler stepSizes; until the first reversal it may move
// after every answer (PsychoPy's applyInitialRule).
struct StaircaseSettings {
  double start = 1.0;
  int up = 1;
  int down = 2;
  std::vector<double> step_sizes{1.0};
  StepType step_type = StepType::linear;
  bool initial_one_down = true;
  double min_level = 0.0;
  double max_level = 1e300;
  int stop_reversals = 10;   // finished after this many reversals...
  int max_trials = 1000;     // ...or this many trials
  int average_reversals = 6; // estimate(): the mean of the last this many reversal levels
};

enum class Placement : std::uint8_t { mean, mode, quantile };

// QUEST (Watson & Pelli 1983, "QUEST: a Bayesian adaptive psychometric method", P&P 33(2)):
// a Gaussian prior on log10 threshold, the posterior on a grid updated by a Weibull in log10
// level, psi(x) = delta*gamma + (1-delta)(1 - (1-gamma) exp(-10^(beta (x - T + eps)))), eps
// placing T at p_threshold; the next level at the posterior's mean (King-Smith et al. 1994),
// mode (Watson & Pelli) or a quantile (Pelli 1987), as PsychoPy's QuestHandler `method`.
// Stops after max_trials, or once the posterior's 5-95 % interval (log10 units) is narrower
// than stop_interval_log10 (PsychoPy's stopInterval). Levels are rounded to the grid.
struct QuestSettings {
  double guess_level = 1.0;        // prior mean, as a level (> 0)
  double prior_sd_log10 = 0.5;
  double p_threshold = 0.82;
  double beta = 3.5;
  double delta = 0.01;
  double gamma = 0.5;
  double grain_log10 = 0.01;
  double range_log10 = 4.0;        // the grid spans guess +- range / 2
  Placement placement = Placement::mean;
  double quantile = 0.5;
  double min_level = 0.0;
  double max_level = 1e300;
  int max_trials = 40;
  double stop_interval_log10 = 0.0; // 0: stop on max_trials only
};

std::unique_ptr<Procedure> make_constant_stimuli(const ConstantStimuliSettings& settings);
std::unique_ptr<Procedure> make_staircase(const StaircaseSettings& settings);
std::unique_ptr<Procedure> make_quest(const QuestSettings& settings);

// QUEST's posterior: the quantile q of the threshold as a level (p_threshold's), for a
// procedure made by make_quest (NaN for any other)
double quest_quantile(const Procedure& quest, double q);

// several procedures of one subject interleaved: each trial goes to one not yet finished,
// drawn from a stream derived from `seed` and the trial's index; finished when all are
struct Interleaved {
  std::vector<std::unique_ptr<Procedure>> procedures;
  std::uint64_t seed = 1;
  std::uint64_t trials = 0;  // told so far, all procedures together

  // the procedure of the next trial (index into procedures); needs !finished()
  std::size_t next() const;
  bool finished() const;
  void tell(bool correct);
};

}  // namespace enact::psychophysics
