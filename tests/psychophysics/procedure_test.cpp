// The procedures' rules on scripted answers (the exact levels a transformed up-down staircase
// presents, its reversals, step sizes and stop; constant stimuli's blocks; QUEST's posterior
// and stop rule), and their state: saved and restored mid-run, they continue exactly as an
// uninterrupted run, and a history from other settings is refused.
#include "core/psychophysics/procedure.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <cmath>
#include <map>
#include <set>

#include "core/psychophysics/observer.h"

namespace enact::psychophysics {
namespace {

// tells `answers` ('C' correct, 'W' wrong), returning the levels presented
std::vector<double> run(Procedure& p, const std::string& answers) {
  std::vector<double> levels;
  for (char a : answers) {
    levels.push_back(p.next_level());
    p.tell(a == 'C');
  }
  return levels;
}

TEST(Staircase, OneUpTwoDownPresentsTheLevelsOfItsRule) {
  StaircaseSettings s;
  s.start = 10.0;
  s.step_sizes = {2.0, 1.0};  // 2 until the first reversal, then 1
  s.initial_one_down = false;
  s.stop_reversals = 3;
  s.average_reversals = 2;
  auto p = make_staircase(s);
  // down after two correct, up after one wrong; reversals at 6 (turns up), 7 (down), 6 (up)
  EXPECT_EQ(run(*p, "CCCCWCCCW"), (std::vector<double>{10, 10, 8, 8, 6, 7, 7, 6, 6}));
  EXPECT_TRUE(p->finished()) << "three reversals";
  EXPECT_DOUBLE_EQ(p->next_level(), 7.0);
  EXPECT_DOUBLE_EQ(p->estimate(), 6.5) << "the mean of the last two reversals";
}

TEST(Staircase, OneUpThreeDownAndTheInitialOneDownRule) {
  StaircaseSettings s;
  s.start = 10.0;
  s.down = 3;
  s.step_sizes = {2.0};
  s.stop_reversals = 100;
  auto p = make_staircase(s);
  // 1-down until the first reversal (at 6), then 3-down
  EXPECT_EQ(run(*p, "CCWCCCCW"), (std::vector<double>{10, 8, 6, 8, 8, 8, 6, 6}));
  EXPECT_DOUBLE_EQ(p->next_level(), 8.0);
  EXPECT_FALSE(p->finished());
}

TEST(Staircase, LogStepsBoundsAndTheTrialLimit) {
  StaircaseSettings s;
  s.start = 100.0;
  s.step_sizes = {0.1};
  s.step_type = StepType::log10;
  s.min_level = 60.0;
  s.max_trials = 6;
  auto p = make_staircase(s);
  const std::vector<double> levels = run(*p, "CCCCCC");
  EXPECT_DOUBLE_EQ(levels[1], 100.0 * std::pow(10.0, -0.1));
  EXPECT_DOUBLE_EQ(levels[2], 100.0 * std::pow(10.0, -0.2));
  EXPECT_DOUBLE_EQ(levels[3], 60.0) << "held at min_level";
  EXPECT_TRUE(p->finished()) << "max_trials";
  EXPECT_TRUE(std::isnan(p->estimate())) << "no reversal";
}

TEST(ConstantStimuli, EveryLevelOncePerBlockInASeededOrder) {
  const ConstantStimuliSettings s{{1.0, 2.0, 3.0, 4.0}, 5, 11};
  auto p = make_constant_stimuli(s);
  const std::vector<double> order = run(*p, std::string(20, 'C'));
  EXPECT_TRUE(p->finished());
  for (std::size_t b = 0; b < 5; ++b) {
    std::vector<double> block(order.begin() + static_cast<long>(4 * b), order.begin() + static_cast<long>(4 * b + 4));
    std::sort(block.begin(), block.end());
    EXPECT_EQ(block, s.levels) << "block " << b;
  }
  auto same = make_constant_stimuli(s);
  EXPECT_EQ(run(*same, std::string(20, 'W')), order) << "the answers do not change the order";
  auto other = make_constant_stimuli({s.levels, 5, 12});
  EXPECT_NE(run(*other, std::string(20, 'C')), order) << "another seed, another order";
}

TEST(Quest, PosteriorFollowsTheAnswersAndLevelsStayOnTheGrid) {
  QuestSettings s;
  s.guess_level = 50.0;
  s.grain_log10 = 0.01;
  for (Placement placement : {Placement::mean, Placement::mode, Placement::quantile}) {
    s.placement = placement;
    auto prior_only = make_quest(s);
    EXPECT_NEAR(prior_only->next_level(), 50.0, 1e-9) << "a symmetric prior centred on the guess";
  }
  s.placement = Placement::mean;
  auto right = make_quest(s), wrong = make_quest(s);
  right->tell(true);
  wrong->tell(false);
  EXPECT_LT(right->estimate(), 50.0) << "a correct answer: the threshold is likely lower";
  EXPECT_GT(wrong->estimate(), 50.0);
  EXPECT_LT(right->next_level(), 50.0);
  const double steps = (std::log10(wrong->next_level()) - std::log10(50.0)) / 0.01;
  EXPECT_NEAR(steps, std::round(steps), 1e-9) << "levels on the grid";
}

TEST(Quest, PlacementAtTheMeanModeOrAQuantileOfThePosterior) {
  QuestSettings s;
  s.guess_level = 50.0;
  // the same answers to each: right, right, wrong at the levels each asks
  auto answered = [&](Placement placement, double quantile) {
    s.placement = placement;
    s.quantile = quantile;
    auto q = make_quest(s);
    run(*q, "CCW");
    return q;
  };
  const auto low = answered(Placement::quantile, 0.2), high = answered(Placement::quantile, 0.8);
  EXPECT_NEAR(low->next_level(), quest_quantile(*low, 0.2), 1e-9 * low->next_level()) << "the posterior's 20 % quantile";
  EXPECT_NEAR(high->next_level(), quest_quantile(*high, 0.8), 1e-9 * high->next_level());
  EXPECT_LT(low->next_level(), high->next_level());
  const auto mean = answered(Placement::mean, 0.5);
  EXPECT_NEAR(std::log10(mean->next_level()), std::round(std::log10(mean->estimate() / 50.0) / 0.01) * 0.01 + std::log10(50.0), 1e-9)
      << "the posterior mean, on the grid";
  EXPECT_TRUE(std::isnan(quest_quantile(*make_staircase({}), 0.5))) << "not a QUEST";
}

TEST(Quest, StopsWhenThePosteriorIntervalIsNarrowEnough) {
  QuestSettings s;
  s.prior_sd_log10 = 0.5;  // prior 5-95 % interval: 2 x 1.645 x 0.5 = 1.645 log10 units
  s.stop_interval_log10 = 1.7;
  EXPECT_TRUE(make_quest(s)->finished());
  s.stop_interval_log10 = 1.6;
  EXPECT_FALSE(make_quest(s)->finished());
  // with an observer, it stops before max_trials once narrow
  s.stop_interval_log10 = 0.25;
  s.max_trials = 1000;
  auto q = make_quest(s);
  const VirtualObserver o{{Shape::weibull, 1.2, 3.5, 0.5, 0.0}, 3};
  while (!q->finished()) q->tell(o.correct(q->history().size(), q->next_level()));
  EXPECT_LT(q->history().size(), 1000u);
  EXPECT_GT(q->history().size(), 5u);
}

// an observer answers `count` trials of p
void answer(Procedure& p, const VirtualObserver& o, std::size_t count) {
  for (std::size_t i = 0; i < count && !p.finished(); ++i) p.tell(o.correct(p.history().size(), p.next_level()));
}

TEST(ProcedureState, RestoredMidRunContinuesExactlyAsUninterrupted) {
  const VirtualObserver o{{Shape::gaussian, 20.0, 6.0, 0.5, 0.02}, 9};
  StaircaseSettings st;
  st.start = 60.0;
  st.step_sizes = {8.0, 4.0, 2.0};
  st.stop_reversals = 12;
  QuestSettings qs;
  qs.guess_level = 40.0;
  std::vector<std::function<std::unique_ptr<Procedure>()>> makers{
      [&] { return make_staircase(st); }, [&] { return make_quest(qs); }, [&] { return make_constant_stimuli({{5, 10, 20, 30, 40}, 6, 4}); }};
  for (const auto& make : makers) {
    auto whole = make();
    answer(*whole, o, 1000);
    auto first = make();
    answer(*first, o, 13);
    const std::string saved = first->save();
    auto resumed = make();
    resumed->restore(saved);
    EXPECT_EQ(resumed->history().size(), 13u);
    answer(*resumed, o, 1000);
    ASSERT_EQ(resumed->history().size(), whole->history().size());
    for (std::size_t i = 0; i < whole->history().size(); ++i) {
      EXPECT_EQ(resumed->history()[i].level, whole->history()[i].level) << i;
      EXPECT_EQ(resumed->history()[i].correct, whole->history()[i].correct) << i;
    }
    EXPECT_EQ(resumed->save(), whole->save());
  }
}

TEST(ProcedureState, AHistoryFromOtherSettingsIsRefused) {
  StaircaseSettings a;
  a.start = 60.0;
  auto p = make_staircase(a);
  p->tell(true);
  p->tell(true);
  StaircaseSettings b = a;
  b.start = 50.0;
  auto other = make_staircase(b);
  EXPECT_THROW(other->restore(p->save()), std::invalid_argument);
  auto same = make_staircase(a);
  EXPECT_NO_THROW(same->restore(p->save()));
}

TEST(Interleaved, DrawsAmongTheUnfinishedSeededAndResumable) {
  auto make = [] {
    Interleaved i;
    i.seed = 21;
    StaircaseSettings up, down;
    up.start = 5.0;
    down.start = 60.0;
    up.step_sizes = down.step_sizes = {4.0, 2.0};
    up.stop_reversals = down.stop_reversals = 8;
    i.procedures.push_back(make_staircase(up));
    i.procedures.push_back(make_staircase(down));
    return i;
  };
  const VirtualObserver o{{Shape::gaussian, 20.0, 6.0, 0.5, 0.0}, 2};
  Interleaved whole = make();
  std::vector<std::size_t> chosen;
  while (!whole.finished()) {
    const std::size_t k = whole.next();
    chosen.push_back(k);
    whole.tell(o.correct(whole.trials, whole.procedures[k]->next_level()));
  }
  for (const auto& p : whole.procedures) EXPECT_TRUE(p->finished());
  // both ran from the start: the first 10 trials went to both
  const std::set<std::size_t> early(chosen.begin(), chosen.begin() + 10);
  EXPECT_EQ(early.size(), 2u);
  // resumed after 11 trials from the procedures' saved histories
  Interleaved first = make();
  for (int t = 0; t < 11; ++t) first.tell(o.correct(first.trials, first.procedures[first.next()]->next_level()));
  Interleaved resumed = make();
  for (std::size_t k = 0; k < 2; ++k) resumed.procedures[k]->restore(first.procedures[k]->save());
  resumed.trials = 11;
  std::vector<std::size_t> rest;
  while (!resumed.finished()) {
    rest.push_back(resumed.next());
    resumed.tell(o.correct(resumed.trials, resumed.procedures[rest.back()]->next_level()));
  }
  EXPECT_EQ(rest, std::vector<std::size_t>(chosen.begin() + 11, chosen.end()));
}

}  // namespace
}  // namespace enact::psychophysics
