// Maximum-likelihood fits: they recover a known function from noise-free counts, equal
// scipy's fit of the same data (scripts/psychophysics.py, another optimiser over another
// parametrisation) to 1e-4, and the bootstrap interval is seeded, holds the fit and narrows
// as trials are added.
#include "core/psychophysics/fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "core/psychophysics/observer.h"
#include "tests/support/test_util.h"

namespace enact::psychophysics {
namespace {

// `trials` answers per level with the expected number correct (rounded)
std::vector<LevelCount> expected_counts(const PsychometricFunction& f, const std::vector<double>& levels, int trials) {
  std::vector<LevelCount> out;
  for (double x : levels) out.push_back({x, trials, static_cast<int>(std::lround(trials * f.probability(x)))});
  return out;
}

// the answers of observer `o` to a procedure run to its end
std::vector<Response> answers(Procedure& p, const VirtualObserver& o) {
  while (!p.finished()) p.tell(o.correct(p.history().size(), p.next_level()));
  return p.history();
}

TEST(Fit, RecoversAKnownFunctionFromNoiseFreeCounts) {
  const std::vector<double> levels{5, 10, 15, 20, 25, 30, 35, 40, 50, 60, 80};
  for (Shape shape : {Shape::gaussian, Shape::weibull}) {
    const PsychometricFunction truth{shape, 30.0, shape == Shape::gaussian ? 9.0 : 3.0, 0.5, 0.03};
    const Fit fit = fit_ml(expected_counts(truth, levels, 1000000), {shape, 0.5, true, 0.0, 0.06});
    EXPECT_NEAR(fit.function.threshold, 30.0, 30.0 * 1e-4) << to_string(shape);
    EXPECT_NEAR(fit.function.spread, truth.spread, truth.spread * 1e-3) << to_string(shape);
    EXPECT_NEAR(fit.function.lapse, 0.03, 1e-4) << to_string(shape);
    EXPECT_GE(fit.log_likelihood, log_likelihood(truth, expected_counts(truth, levels, 1000000)));
  }
}

struct ScipyFit {
  double threshold = 0, spread = 0, lapse = 0, log_likelihood = 0;
};

double json_number(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\": ");
  EXPECT_NE(at, std::string::npos) << key << " in " << json;
  return at == std::string::npos ? NAN : std::stod(json.substr(at + key.size() + 4));
}

ScipyFit scipy_fit(const test::TempDir& dir, const std::vector<LevelCount>& data, const FitSettings& s) {
  const std::string path = dir.file("counts.csv");
  std::ofstream out(path);
  out << "level,trials,correct\n";
  char line[96];
  for (const LevelCount& c : data) {
    std::snprintf(line, sizeof line, "%.17g,%d,%d\n", c.level, c.trials, c.correct);
    out << line;
  }
  out.close();
  const std::string lapse = s.free_lapse ? " --max-lapse " + std::to_string(s.max_lapse) : " --lapse " + std::to_string(s.lapse);
  const test::RunResult r = test::run(std::string(ENACT_PYTHON) + " " + test::source_path("scripts/psychophysics.py") + " fit " + path + " --shape " +
                                      to_string(s.shape) + lapse);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return {json_number(r.out, "threshold"), json_number(r.out, "spread"), json_number(r.out, "lapse"), json_number(r.out, "log_likelihood")};
}

TEST(Fit, EqualsScipysMaximumLikelihoodFitTo1e4) {
  const test::TempDir dir;
  // data sets: constant stimuli, a staircase's and QUEST's answers, with lapses fitted or fixed
  const VirtualObserver g{{Shape::gaussian, 40.0, 15.0, 0.5, 0.02}, 31};
  const VirtualObserver w{{Shape::weibull, 40.0, 3.0, 0.5, 0.02}, 32};
  auto constant = make_constant_stimuli({{10, 20, 30, 40, 50, 60, 80}, 20, 5});
  StaircaseSettings st;
  st.start = 120.0;
  st.step_sizes = {16.0, 8.0, 4.0};
  st.min_level = 1.0;
  st.stop_reversals = 14;
  auto staircase = make_staircase(st);
  QuestSettings qs;
  qs.guess_level = 60.0;
  qs.max_trials = 80;
  auto quest = make_quest(qs);
  struct Case {
    const char* name;
    std::vector<LevelCount> data;
    FitSettings settings;
  };
  const std::vector<Response> constant_answers = answers(*constant, g);
  const std::vector<Case> cases{
      {"constant, gaussian, free lapse", tally(constant_answers), {Shape::gaussian, 0.5, true, 0.0, 0.06}},
      {"constant, weibull, fixed lapse", tally(constant_answers), {Shape::weibull, 0.5, false, 0.01, 0.06}},
      {"staircase, gaussian, free lapse", tally(answers(*staircase, g)), {Shape::gaussian, 0.5, true, 0.0, 0.06}},
      {"quest, weibull, free lapse", tally(answers(*quest, w)), {Shape::weibull, 0.5, true, 0.0, 0.06}},
  };
  for (const Case& c : cases) {
    const Fit ours = fit_ml(c.data, c.settings);
    const ScipyFit theirs = scipy_fit(dir, c.data, c.settings);
    EXPECT_NEAR(ours.function.threshold, theirs.threshold, 1e-4 * theirs.threshold) << c.name;
    EXPECT_NEAR(ours.function.spread, theirs.spread, 1e-4 * theirs.spread) << c.name;
    EXPECT_NEAR(ours.function.lapse, theirs.lapse, 1e-4) << c.name;
    EXPECT_NEAR(ours.log_likelihood, theirs.log_likelihood, 1e-6) << c.name;
  }
}

TEST(Bootstrap, SeededHoldsTheFitAndNarrowsWithMoreTrials) {
  const PsychometricFunction truth{Shape::gaussian, 30.0, 10.0, 0.5, 0.0};
  const std::vector<double> levels{10, 20, 30, 40, 50};
  const FitSettings s{Shape::gaussian, 0.5, false, 0.0, 0.06};
  const std::vector<LevelCount> few = expected_counts(truth, levels, 40), many = expected_counts(truth, levels, 640);
  const Fit fit_few = fit_ml(few, s), fit_many = fit_ml(many, s);
  const Interval a = bootstrap_threshold(resample_levels(few), s, fit_few, 300, 8), again = bootstrap_threshold(resample_levels(few), s, fit_few, 300, 8);
  EXPECT_EQ(a.low, again.low);
  EXPECT_EQ(a.high, again.high);
  EXPECT_TRUE(a.covers(fit_few.function.threshold));
  const Interval b = bootstrap_threshold(resample_levels(many), s, fit_many, 300, 8);
  EXPECT_TRUE(b.covers(fit_many.function.threshold));
  // 16 times the trials: the width shrinks about 4 times (sampling noise of 300 replicates
  // and the percentiles' spread keep it within 3 to 5.3)
  const double ratio = (a.high - a.low) / (b.high - b.low);
  EXPECT_GT(ratio, 3.0);
  EXPECT_LT(ratio, 5.3);
}

TEST(ProfileInterval, MatchesTheFisherInformationIntervalOnLargeSamples) {
  // spread and lapse held: the profile is the likelihood of the threshold alone, whose 95 %
  // interval tends to t +- 1.96 / sqrt(I), I = sum n psi'(x)^2 / (psi (1 - psi))
  const PsychometricFunction truth{Shape::gaussian, 30.0, 10.0, 0.5, 0.0};
  const std::vector<double> levels{10, 20, 30, 40, 50};
  FitSettings s{Shape::gaussian, 0.5, false, 0.0, 0.06};
  s.spread = 10.0;
  const std::vector<LevelCount> data = expected_counts(truth, levels, 20000);
  const Fit fit = fit_ml(data, s);
  double information = 0.0;
  for (const LevelCount& c : data) {
    const double z = (c.level - fit.function.threshold) / 10.0;
    const double slope = 0.5 * std::exp(-0.5 * z * z) / std::sqrt(2.0 * M_PI) / 10.0;
    const double p = fit.function.probability(c.level);
    information += c.trials * slope * slope / (p * (1.0 - p));
  }
  const double half = 1.959964 / std::sqrt(information);
  const Interval profile = profile_threshold(data, s, fit);
  EXPECT_NEAR(profile.low, fit.function.threshold - half, 0.02 * half);
  EXPECT_NEAR(profile.high, fit.function.threshold + half, 0.02 * half);
  // with the spread fitted too, the threshold is less certain: a wider interval
  s.spread = 0.0;
  const Fit free_fit = fit_ml(data, s);
  const Interval wider = profile_threshold(data, s, free_fit);
  EXPECT_GT(wider.high - wider.low, profile.high - profile.low);
  EXPECT_TRUE(wider.covers(30.0));
}

}  // namespace
}  // namespace enact::psychophysics
