#include "core/psychophysics/procedure.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/math/random.h"
#include "core/psychophysics/psychometric.h"

namespace enact::psychophysics {

Procedure::~Procedure() = default;

void Procedure::tell(bool correct) {
  const double level = next_level();
  history_.push_back({level, correct});
  update(level, correct);
}

std::string Procedure::save() const {
  std::string out;
  char line[64];
  for (const Response& r : history_) {
    std::snprintf(line, sizeof line, "%.17g %d\n", r.level, r.correct ? 1 : 0);
    out += line;
  }
  return out;
}

void Procedure::restore(const std::string& saved) {
  history_.clear();
  reset();
  std::istringstream in(saved);
  double level = 0.0;
  int correct = 0;
  while (in >> level >> correct) {
    const double asked = next_level();
    if (finished() || std::abs(asked - level) > 1e-12 * std::max(1.0, std::abs(level))) {
      throw std::invalid_argument("trial " + std::to_string(history_.size() + 1) + " was at level " + std::to_string(level) +
                                  " but this procedure asks for " + (finished() ? std::string("none (finished)") : std::to_string(asked)));
    }
    tell(correct != 0);
  }
}

namespace {

class ConstantStimuli final : public Procedure {
 public:
  explicit ConstantStimuli(const ConstantStimuliSettings& s) : s_(s) {
    if (s_.levels.empty() || s_.repetitions < 1) throw std::invalid_argument("constant stimuli need levels and repetitions >= 1");
    // block b: a Fisher-Yates permutation from the stream of (seed, b)
    const std::size_t n = s_.levels.size();
    for (int b = 0; b < s_.repetitions; ++b) {
      std::vector<double> block = s_.levels;
      math::Random r(math::derive_seed(s_.seed, static_cast<std::uint64_t>(b)));
      for (std::size_t i = n; i > 1; --i) std::swap(block[i - 1], block[r.below(i)]);
      order_.insert(order_.end(), block.begin(), block.end());
    }
  }
  double next_level() const override { return order_[std::min(done_, order_.size() - 1)]; }
  bool finished() const override { return done_ >= order_.size(); }
  double estimate() const override { return std::numeric_limits<double>::quiet_NaN(); }

 protected:
  void update(double, bool) override { ++done_; }
  void reset() override { done_ = 0; }

 private:
  ConstantStimuliSettings s_;
  std::vector<double> order_;
  std::size_t done_ = 0;
};

class Staircase final : public Procedure {
 public:
  explicit Staircase(const StaircaseSettings& s) : s_(s) {
    if (s_.up < 1 || s_.down < 1 || s_.step_sizes.empty() || s_.stop_reversals < 1 || s_.max_trials < 1 || s_.average_reversals < 1) {
      throw std::invalid_argument("a staircase needs up, down, stop_reversals, max_trials, average_reversals >= 1 and a step size");
    }
    for (double step : s_.step_sizes) {
      if (!(step > 0.0)) throw std::invalid_argument("staircase step sizes must be > 0");
    }
    reset();
  }
  double next_level() const override { return level_; }
  bool finished() const override {
    return static_cast<int>(reversals_.size()) >= s_.stop_reversals || static_cast<int>(history().size()) >= s_.max_trials;
  }
  double estimate() const override {
    if (reversals_.empty()) return std::numeric_limits<double>::quiet_NaN();
    const std::size_t n = std::min(reversals_.size(), static_cast<std::size_t>(s_.average_reversals));
    double sum = 0.0;
    for (std::size_t i = reversals_.size() - n; i < reversals_.size(); ++i) {
      sum += s_.step_type == StepType::log10 ? std::log10(reversals_[i]) : reversals_[i];
    }
    return s_.step_type == StepType::log10 ? std::pow(10.0, sum / static_cast<double>(n)) : sum / static_cast<double>(n);
  }

 protected:
  void reset() override {
    level_ = std::clamp(s_.start, s_.min_level, s_.max_level);
    correct_run_ = wrong_run_ = 0;
    direction_ = 0;
    reversals_.clear();
  }

  void update(double level, bool correct) override {
    // the transformed rule; 1-down (and 1-up) before the first reversal if asked
    const bool initial = s_.initial_one_down && reversals_.empty();
    int move = 0;
    if (correct) {
      wrong_run_ = 0;
      if (++correct_run_ >= (initial ? 1 : s_.down)) move = -1;
    } else {
      correct_run_ = 0;
      if (++wrong_run_ >= (initial ? 1 : s_.up)) move = +1;
    }
    if (move == 0) return;
    correct_run_ = wrong_run_ = 0;
    // a reversal: a move against the previous one, at the level where it turned
    if (direction_ != 0 && move != direction_) reversals_.push_back(level);
    direction_ = move;
    const double step = s_.step_sizes[std::min(reversals_.size(), s_.step_sizes.size() - 1)];
    const double next = s_.step_type == StepType::linear ? level + move * step : level * std::pow(10.0, move * step);
    level_ = std::clamp(next, s_.min_level, s_.max_level);
  }

 private:
  StaircaseSettings s_;
  double level_ = 0.0;
  int correct_run_ = 0, wrong_run_ = 0;
  int direction_ = 0;  // the last move: -1 down, +1 up, 0 none yet
  std::vector<double> reversals_;
};

class Quest final : public Procedure {
 public:
  explicit Quest(const QuestSettings& s) : s_(s) {
    if (!(s_.guess_level > 0.0) || !(s_.prior_sd_log10 > 0.0) || !(s_.grain_log10 > 0.0) || !(s_.range_log10 > s_.grain_log10) || !(s_.beta > 0.0) ||
        !(s_.gamma >= 0.0 && s_.gamma < 1.0) || !(s_.delta >= 0.0 && s_.delta < 1.0) || !(s_.p_threshold > s_.gamma && s_.p_threshold < 1.0) ||
        !(s_.quantile > 0.0 && s_.quantile < 1.0) || s_.max_trials < 1) {
      throw std::invalid_argument("QUEST settings out of range");
    }
    // eps: psi(T) = p_threshold, on the function without its lapse term
    const double p = (s_.p_threshold - s_.delta * s_.gamma) / (1.0 - s_.delta);
    eps_ = std::log10(-std::log((1.0 - p) / (1.0 - s_.gamma))) / s_.beta;
    centre_ = std::log10(s_.guess_level);
    const int half = static_cast<int>(std::round(s_.range_log10 / 2.0 / s_.grain_log10));
    for (int i = -half; i <= half; ++i) grid_.push_back(centre_ + i * s_.grain_log10);
    reset();
  }

  double next_level() const override {
    double t = centre_;
    if (s_.placement == Placement::mean) t = mean();
    if (s_.placement == Placement::mode) t = grid_[static_cast<std::size_t>(std::max_element(log_posterior_.begin(), log_posterior_.end()) - log_posterior_.begin())];
    if (s_.placement == Placement::quantile) t = quantile(s_.quantile);
    // on the grid, within the bounds
    const double on_grid = centre_ + std::round((t - centre_) / s_.grain_log10) * s_.grain_log10;
    return std::clamp(std::pow(10.0, on_grid), s_.min_level, s_.max_level);
  }
  bool finished() const override {
    if (static_cast<int>(history().size()) >= s_.max_trials) return true;
    return s_.stop_interval_log10 > 0.0 && quantile(0.95) - quantile(0.05) < s_.stop_interval_log10;
  }
  double estimate() const override { return std::pow(10.0, mean()); }
  double quantile_level(double q) const { return std::pow(10.0, quantile(q)); }

 protected:
  void reset() override {
    log_posterior_.assign(grid_.size(), 0.0);
    for (std::size_t i = 0; i < grid_.size(); ++i) {
      const double z = (grid_[i] - centre_) / s_.prior_sd_log10;
      log_posterior_[i] = -0.5 * z * z;
    }
  }

  void update(double level, bool correct) override {
    const double x = std::log10(level);
    for (std::size_t i = 0; i < grid_.size(); ++i) {
      const double p = s_.delta * s_.gamma + (1.0 - s_.delta) * (1.0 - (1.0 - s_.gamma) * std::exp(-std::pow(10.0, s_.beta * (x - grid_[i] + eps_))));
      log_posterior_[i] += std::log(correct ? p : 1.0 - p);
    }
  }

 private:
  // the normalised posterior
  std::vector<double> weights() const {
    const double top = *std::max_element(log_posterior_.begin(), log_posterior_.end());
    std::vector<double> w(grid_.size());
    double sum = 0.0;
    for (std::size_t i = 0; i < w.size(); ++i) sum += (w[i] = std::exp(log_posterior_[i] - top));
    for (double& v : w) v /= sum;
    return w;
  }
  double mean() const {
    const std::vector<double> w = weights();
    double m = 0.0;
    for (std::size_t i = 0; i < w.size(); ++i) m += w[i] * grid_[i];
    return m;
  }
  double quantile(double q) const {
    const std::vector<double> w = weights();
    double cumulative = 0.0;
    for (std::size_t i = 0; i < w.size(); ++i) {
      if ((cumulative += w[i]) >= q) return grid_[i];
    }
    return grid_.back();
  }

  QuestSettings s_;
  double eps_ = 0.0, centre_ = 0.0;
  std::vector<double> grid_;           // candidate log10 thresholds
  std::vector<double> log_posterior_;  // unnormalised
};

}  // namespace

std::unique_ptr<Procedure> make_constant_stimuli(const ConstantStimuliSettings& settings) { return std::make_unique<ConstantStimuli>(settings); }
std::unique_ptr<Procedure> make_staircase(const StaircaseSettings& settings) { return std::make_unique<Staircase>(settings); }
std::unique_ptr<Procedure> make_quest(const QuestSettings& settings) { return std::make_unique<Quest>(settings); }

double quest_quantile(const Procedure& quest, double q) {
  const auto* p = dynamic_cast<const Quest*>(&quest);
  return p ? p->quantile_level(q) : std::numeric_limits<double>::quiet_NaN();
}

std::size_t Interleaved::next() const {
  std::vector<std::size_t> open;
  for (std::size_t i = 0; i < procedures.size(); ++i) {
    if (!procedures[i]->finished()) open.push_back(i);
  }
  math::Random r(math::derive_seed(seed, trials));
  return open.empty() ? 0 : open[r.below(open.size())];
}

bool Interleaved::finished() const {
  return std::all_of(procedures.begin(), procedures.end(), [](const auto& p) { return p->finished(); });
}

void Interleaved::tell(bool correct) {
  procedures[next()]->tell(correct);
  ++trials;
}

}  // namespace enact::psychophysics
