#pragma once
// Maximum-likelihood fits of a psychometric function to discrimination answers, and
// parametric bootstrap confidence intervals of the threshold (Wichmann & Hill 2001, "The
// psychometric function: I. Fitting, sampling and goodness of fit" and "II. Bootstrap-based
// confidence intervals and sampling", P&P 63(8)). The guess rate is fixed (0.5 for two
// intervals); the lapse rate is fixed or fitted within [0, max_lapse]. The likelihood is
// maximised by Nelder-Mead (restarted at its optimum until it no longer moves) over the
// threshold (its log for a Weibull), the log spread and the lapse. scripts/psychophysics.py
// fits the same data with scipy (tests/psychophysics: equal to 1e-4).
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/psychophysics/procedure.h"
#include "core/psychophysics/psychometric.h"

namespace enact::psychophysics {

// the answers at one level
struct LevelCount {
  double level = 0.0;
  int trials = 0;
  int correct = 0;
};

// answers grouped by level, in increasing level
std::vector<LevelCount> tally(const std::vector<Response>& responses);

struct FitSettings {
  Shape shape = Shape::gaussian;
  double guess = 0.5;
  bool free_lapse = true;
  double lapse = 0.0;       // when fixed
  double max_lapse = 0.06;  // when fitted
  double spread = 0.0;      // > 0: the spread held at this value (e.g. a Weibull exponent
                            // known from the literature); 0: fitted
};

struct Fit {
  PsychometricFunction function;
  double log_likelihood = 0.0;  // sum of k log psi + (n - k) log(1 - psi) (no binomial terms)
};

// the log-likelihood of `data` under `f`
double log_likelihood(const PsychometricFunction& f, const std::vector<LevelCount>& data);

// the maximum-likelihood fit; throws std::invalid_argument on data with no trials or a
// level <= 0 for a Weibull
Fit fit_ml(const std::vector<LevelCount>& data, const FitSettings& settings);

struct Interval {
  double low = 0.0;
  double high = 0.0;
  bool covers(double value) const { return low <= value && value <= high; }
};

// a bootstrap sample: the answers an observer with function f gives, drawn from `seed`
using Resample = std::function<std::vector<LevelCount>(const PsychometricFunction& f, std::uint64_t seed)>;

// the percentile interval (`confidence`, e.g. 0.95) of the threshold over `replicates`
// parametric bootstrap samples drawn from the fitted function, each fitted again; seeded.
// With an adaptive procedure the levels depend on the answers, so a sample must run the
// procedure again with the fitted function as the observer (resample_procedure); with fixed
// levels (constant stimuli) resample_levels draws the same number of answers at each level.
Interval bootstrap_threshold(const Resample& resample, const FitSettings& settings, const Fit& fit, int replicates, std::uint64_t seed,
                             double confidence = 0.95);
// the profile-likelihood interval of the threshold: the thresholds t whose best fit with t
// held (spread and lapse refitted) has a log-likelihood within chi2(1, confidence) / 2 of
// the maximum (Wilks; Venzon & Moolgavkar 1988). It allows for a slope the data barely
// constrain, which adaptive procedures' data often do not (Kaernbach 2001, "Slope bias of
// psychometric functions derived from adaptive data", P&P 63(8)): the parametric bootstrap
// is then too narrow. An end the data do not bound is at infinity (or 0 for a Weibull).
Interval profile_threshold(const std::vector<LevelCount>& data, const FitSettings& settings, const Fit& fit, double confidence = 0.95);

Resample resample_levels(const std::vector<LevelCount>& data);
// `make` gives the procedure in its first state
Resample resample_procedure(std::function<std::unique_ptr<Procedure>()> make);

}  // namespace enact::psychophysics
