// Psychometric functions: the threshold is where F = 0.5 (75 % correct with two intervals and
// no lapse) for both shapes, level_at inverts probability, and the virtual observer answers
// correctly as often as its function says, the same way every time.
#include "core/psychophysics/psychometric.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/psychophysics/observer.h"

namespace enact::psychophysics {
namespace {

TEST(Psychometric, ThresholdIsSeventyFivePercentCorrectForBothShapes) {
  for (Shape shape : {Shape::gaussian, Shape::weibull}) {
    const PsychometricFunction f{shape, 30.0, shape == Shape::gaussian ? 12.0 : 2.5, 0.5, 0.0};
    EXPECT_NEAR(f.probability(30.0), 0.75, 1e-12) << to_string(shape);
    EXPECT_LT(f.probability(20.0), 0.75);
    EXPECT_GT(f.probability(40.0), 0.75);
  }
  // the Weibull's own form: 1 - exp(-(x/alpha)^beta) with alpha = threshold / ln2^(1/beta)
  const PsychometricFunction w{Shape::weibull, 30.0, 2.5, 0.5, 0.0};
  const double alpha = 30.0 / std::pow(std::log(2.0), 1.0 / 2.5);
  EXPECT_NEAR(w.core(41.0), 1.0 - std::exp(-std::pow(41.0 / alpha, 2.5)), 1e-14);
  EXPECT_EQ(w.core(0.0), 0.0);
  // the lapse lowers the ceiling: psi -> 1 - lapse
  const PsychometricFunction lapsing{Shape::gaussian, 30.0, 5.0, 0.5, 0.04};
  EXPECT_NEAR(lapsing.probability(1e6), 0.96, 1e-12);
}

TEST(Psychometric, LevelAtInvertsProbability) {
  for (Shape shape : {Shape::gaussian, Shape::weibull}) {
    const PsychometricFunction f{shape, 30.0, shape == Shape::gaussian ? 12.0 : 2.5, 0.5, 0.03};
    for (double p : {0.55, 0.707, 0.794, 0.9}) EXPECT_NEAR(f.probability(f.level_at(p)), p, 1e-12) << to_string(shape) << " " << p;
  }
}

TEST(Psychometric, NormalQuantileInvertsTheCdf) {
  for (double p : {1e-10, 0.025, 0.3, 0.5, 0.75, 0.975, 1.0 - 1e-9}) EXPECT_NEAR(normal_cdf(normal_quantile(p)), p, 1e-14 + 1e-12 * p) << p;
  EXPECT_NEAR(normal_quantile(0.975), 1.959963984540054, 1e-12);
}

TEST(VirtualObserver, AnswersAsOftenAsItsFunctionSaysAndTheSameEveryTime) {
  const VirtualObserver o{{Shape::gaussian, 30.0, 10.0, 0.5, 0.02}, 77};
  // 20000 trials at 3 levels: the proportion correct within 4 binomial SDs of psi
  for (double level : {15.0, 30.0, 45.0}) {
    const double p = o.function.probability(level);
    int correct = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) correct += o.correct(static_cast<std::uint64_t>(i), level) ? 1 : 0;
    EXPECT_NEAR(static_cast<double>(correct) / n, p, 4.0 * std::sqrt(p * (1 - p) / n)) << level;
  }
  const VirtualObserver again = o;
  const VirtualObserver other{o.function, 78};
  int same = 0, differ = 0;
  for (std::uint64_t i = 0; i < 1000; ++i) {
    same += o.correct(i, 30.0) == again.correct(i, 30.0);
    differ += o.correct(i, 30.0) != other.correct(i, 30.0);
  }
  EXPECT_EQ(same, 1000);
  EXPECT_GT(differ, 200) << "another seed answers otherwise";
  // without lapses, far above threshold: always the larger interval; at 0 the other as often
  const VirtualObserver sure{{Shape::gaussian, 30.0, 10.0, 0.5, 0.0}, 5};
  int other_named = 0;
  for (std::uint64_t i = 0; i < 1000; ++i) {
    EXPECT_EQ(sure.chosen_interval(i, 1e6, 1 + static_cast<int>(i % 2)), 1 + static_cast<int>(i % 2));
    other_named += sure.chosen_interval(i, -1e6, 1) == 2;
  }
  EXPECT_NEAR(other_named, 500, 4 * std::sqrt(250.0)) << "at chance, half the answers name the other interval";
}

}  // namespace
}  // namespace enact::psychophysics
