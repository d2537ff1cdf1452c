// The procedures and fits validated on virtual observers with known functions, each figure
// printed and bounded by its own sampling error (no bound that a wrong program would pass):
// - transformed up-down staircases converge on Levitt's (1971) points, 70.7 % correct for
//   1-up-2-down and 79.4 % for 1-up-3-down;
// - QUEST's posterior is calibrated: with observers drawn from its prior and answering with
//   its own psychometric function, the posterior's 5-95 % interval holds the true threshold
//   in 90 % of them, and its mean errs by 0 on average (Bayes: both exact in expectation);
// - the fitted JND's 95 % interval covers the true JND in 92-98 % of 200 observers with
//   known Weber fractions, for the 1-up-2-down staircase and QUEST (issue 28): the
//   profile-likelihood interval; the bootstrap's coverage is printed beside it (it is lower:
//   see docs/experiments.md, "Discrimination experiments").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <utility>

#include "core/math/random.h"
#include "core/psychophysics/fit.h"
#include "core/psychophysics/observer.h"
#include "core/psychophysics/procedure.h"

namespace enact::psychophysics {
namespace {

struct Moments {
  double sum = 0.0, sum_sq = 0.0;
  int n = 0;
  void add(double v) {
    sum += v;
    sum_sq += v * v;
    ++n;
  }
  double mean() const { return sum / n; }
  double sd() const { return std::sqrt(std::max(0.0, (sum_sq - sum * sum / n) / (n - 1))); }
  double standard_error() const { return sd() / std::sqrt(static_cast<double>(n)); }
};

void run_to_end(Procedure& p, const VirtualObserver& o) {
  while (!p.finished()) p.tell(o.correct(p.history().size(), p.next_level()));
}

// the staircase's mean estimate (mean of the last reversals) over `runs` observers, against
// the level where psi = target: within 3 standard errors plus half a step (the grid of
// levels a fixed-step staircase can visit)
void expect_converges(int down, double target) {
  const PsychometricFunction f{Shape::gaussian, 30.0, 10.0, 0.5, 0.0};
  StaircaseSettings s;
  s.start = 60.0;
  s.down = down;
  s.step_sizes = {4.0, 1.0};
  s.stop_reversals = 40;
  s.average_reversals = 30;
  s.max_trials = 100000;
  Moments level;
  const int runs = 300;
  for (int i = 0; i < runs; ++i) {
    auto p = make_staircase(s);
    run_to_end(*p, {f, math::derive_seed(1000 + static_cast<std::uint64_t>(down), static_cast<std::uint64_t>(i))});
    level.add(p->estimate());
  }
  const double expected = f.level_at(target);
  const double tolerance = 3.0 * level.standard_error() + 0.5 * s.step_sizes.back();
  std::printf("figure: 1-up-%d-down over %d staircases: mean level %.3f (psi %.4f), expected %.3f (psi %.4f), tolerance +-%.3f\n", down, runs,
              level.mean(), f.probability(level.mean()), expected, target, tolerance);
  EXPECT_NEAR(level.mean(), expected, tolerance) << "1-up-" << down << "-down";
}

TEST(Validation, OneUpTwoDownConvergesOn707Percent) { expect_converges(2, std::sqrt(0.5)); }
TEST(Validation, OneUpThreeDownConvergesOn794Percent) { expect_converges(3, std::cbrt(0.5)); }

TEST(Validation, QuestPosteriorIsCalibratedAndUnbiased) {
  QuestSettings s;
  s.guess_level = 100.0;
  s.prior_sd_log10 = 0.3;
  s.max_trials = 40;
  // QUEST's psi as an observer: a Weibull of exponent beta, lapse delta (1 - gamma)
  const double eps = std::log10(-std::log((1.0 - (s.p_threshold - s.delta * s.gamma) / (1.0 - s.delta)) / (1.0 - s.gamma))) / s.beta;
  const int observers = 400;
  int inside = 0;
  Moments error;
  math::Random draw(2024);
  for (int i = 0; i < observers; ++i) {
    const double t = std::log10(s.guess_level) + s.prior_sd_log10 * draw.normal();
    const PsychometricFunction f{Shape::weibull, std::pow(10.0, t - eps) * std::pow(std::log(2.0), 1.0 / s.beta), s.beta, s.gamma, s.delta * (1.0 - s.gamma)};
    ASSERT_NEAR(std::log10(f.level_at(s.p_threshold)), t, 1e-9) << "the observer's p_threshold level is QUEST's T";
    auto q = make_quest(s);
    run_to_end(*q, {f, math::derive_seed(77, static_cast<std::uint64_t>(i))});
    inside += std::log10(quest_quantile(*q, 0.05)) <= t && t <= std::log10(quest_quantile(*q, 0.95));
    error.add(std::log10(q->estimate()) - t);
  }
  const double coverage = static_cast<double>(inside) / observers;
  const double coverage_sd = std::sqrt(0.9 * 0.1 / observers);
  std::printf("figure: QUEST, %d trials, %d observers: 5-95 %% posterior interval holds the threshold in %.1f %% (90 %% +- %.1f), error %.4f +- %.4f log10 (rms %.4f)\n",
              s.max_trials, observers, 100 * coverage, 300 * coverage_sd, error.mean(), error.standard_error(),
              std::sqrt(error.sum_sq / observers));
  EXPECT_NEAR(coverage, 0.90, 3.0 * coverage_sd);
  EXPECT_NEAR(error.mean(), 0.0, 3.0 * error.standard_error());
  // 40 trials tell more than the prior: the error is well below the prior's spread
  EXPECT_LT(std::sqrt(error.sum_sq / observers), 0.5 * s.prior_sd_log10);
}

// 200 observers with Weber fractions from 0.05 to 0.25 of a 600 N/m reference, Weibull
// exponents from 2.5 to 4.5 and a 2 % lapse rate, each run through a procedure, fitted
// (Weibull of exponent 3.5, lapse fitted in [0, 0.06]) and given both intervals (the
// bootstrap runs the procedure again). Returns the share of profile-likelihood (first)
// and bootstrap (second) intervals holding the true JND.
std::pair<double, double> jnd_coverage(const char* name, const std::function<std::unique_ptr<Procedure>()>& make) {
  constexpr double kReference_n_per_m = 600.0;
  const int observers = 200;
  int profile_covered = 0, bootstrap_covered = 0;
  Moments weber_error;
  math::Random draw(42);
  for (int i = 0; i < observers; ++i) {
    const double weber = 0.05 + 0.2 * draw.uniform();
    const double exponent = 2.5 + 2.0 * draw.uniform();
    const double jnd_n_per_m = weber * kReference_n_per_m;
    const PsychometricFunction f{Shape::weibull, jnd_n_per_m, exponent, 0.5, 0.02};
    const Resample run = resample_procedure(make);
    const std::vector<LevelCount> data = run(f, math::derive_seed(900, static_cast<std::uint64_t>(i)));
    FitSettings settings{Shape::weibull, 0.5, true, 0.0, 0.06};
    settings.spread = 3.5;
    const Fit fit = fit_ml(data, settings);
    profile_covered += profile_threshold(data, settings, fit).covers(jnd_n_per_m);
    const Interval bootstrap = bootstrap_threshold(run, settings, fit, 100, math::derive_seed(901, static_cast<std::uint64_t>(i)));
    bootstrap_covered += bootstrap.covers(jnd_n_per_m);
    weber_error.add(fit.function.threshold / kReference_n_per_m - weber);
  }
  const std::pair<double, double> coverage{static_cast<double>(profile_covered) / observers, static_cast<double>(bootstrap_covered) / observers};
  std::printf("figure: %s, %d observers: the 95 %% interval covers the true JND in %.1f %% (profile likelihood), %.1f %% (bootstrap); "
              "Weber fraction error %.4f +- %.4f (sd %.4f)\n",
              name, observers, 100 * coverage.first, 100 * coverage.second, weber_error.mean(), weber_error.standard_error(), weber_error.sd());
  return coverage;
}

// issue 28: 92-98 % (95 % +- 2 binomial SDs of 200 observers)
void expect_nominal(double coverage) {
  EXPECT_GE(coverage, 0.92);
  EXPECT_LE(coverage, 0.98);
}

// adaptive data constrain the slope poorly and bias it steep (Kaernbach 2001), so the
// exponent is held at QUEST's 3.5 (Watson & Pelli 1983) while the observers' vary; the
// bootstrap then still undercovers (printed), the profile likelihood does not
TEST(Validation, JndIntervalsCoverTheTruthForTheStaircase) {
  const auto coverage = jnd_coverage("1-up-2-down staircase, 24 reversals", [] {
    StaircaseSettings s;
    s.start = 300.0;
    s.step_sizes = {0.2, 0.1, 0.05};
    s.step_type = StepType::log10;
    s.stop_reversals = 24;
    s.max_trials = 400;
    return make_staircase(s);
  });
  expect_nominal(coverage.first);
}

TEST(Validation, JndIntervalsCoverTheTruthForQuest) {
  const auto coverage = jnd_coverage("QUEST at 75 %, 60 trials", [] {
    QuestSettings s;
    s.guess_level = 90.0;
    s.p_threshold = 0.75;
    s.max_trials = 60;
    return make_quest(s);
  });
  expect_nominal(coverage.first);
}

}  // namespace
}  // namespace enact::psychophysics
