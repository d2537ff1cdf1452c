// The experiment file and its plan: balanced orders are Williams Latin squares, random
// orders are seeded per subject, practice and familiarisation trials are placed, seeds
// follow subjects, and bad files are refused with file:line and the fix.
#include "core/experiment/experiment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include "core/config/yaml.h"
#include "tests/support/test_util.h"
#include "tests/support/refusal.h"

namespace enact::experiment {
namespace {

// an experiment file in `dir` with the shipped subject and trial graph, and `extra` lines
std::string write_experiment(const test::TempDir& dir, const std::string& extra) {
  const std::string path = dir.file("exp.yaml");
  test::write_file(path, "name: t\nseed: 5\nsubjects: 4\nvirtual_subject: " + test::source_path("launch/experiments/subjects/quick.yaml") +
                             "\nconditions: [CM0, CM1, CM2, CM3]\nlimit_s: 10\ngraph: " + test::source_path("launch/experiments/trial_rt.yaml") +
                             "\n" + extra);
  return path;
}

std::string error_of(const std::string& text) {
  return test::error_of_file("bad.yaml", text, [](const std::string& path) { load_experiment(path); });
}

TEST(Plan, BalancedOrderIsAWilliamsSquare) {
  for (std::size_t n : {2u, 3u, 4u, 5u}) {
    const std::size_t rows = n % 2 == 0 ? n : 2 * n;
    std::map<std::pair<std::size_t, std::size_t>, int> at, follows;
    for (std::size_t s = 0; s < rows; ++s) {
      const std::vector<std::size_t> order = condition_order(Order::balanced, n, s, 1);
      ASSERT_EQ(std::set<std::size_t>(order.begin(), order.end()).size(), n) << "a permutation";
      for (std::size_t j = 0; j < n; ++j) at[{order[j], j}] += 1;
      for (std::size_t j = 0; j + 1 < n; ++j) follows[{order[j], order[j + 1]}] += 1;
    }
    // each condition equally often in each position, each ordered pair equally often adjacent
    EXPECT_EQ(at.size(), n * n) << n;
    for (const auto& [key, count] : at) EXPECT_EQ(count, static_cast<int>(rows / n)) << n;
    EXPECT_EQ(follows.size(), n * (n - 1)) << n;
    for (const auto& [key, count] : follows) EXPECT_EQ(count, static_cast<int>(rows / n)) << n;
  }
  EXPECT_EQ(condition_order(Order::balanced, 4, 0, 1), (std::vector<std::size_t>{0, 1, 3, 2})) << "Williams' first row: 0, 1, n-1, 2, ...";
}

TEST(Plan, RandomOrderIsSeededPerSubject) {
  std::set<std::vector<std::size_t>> seen;
  for (std::size_t s = 0; s < 12; ++s) {
    const std::vector<std::size_t> order = condition_order(Order::random, 4, s, 42);
    EXPECT_EQ(order, condition_order(Order::random, 4, s, 42)) << "the same seed, the same order";
    EXPECT_EQ(std::set<std::size_t>(order.begin(), order.end()).size(), 4u);
    seen.insert(order);
  }
  EXPECT_GT(seen.size(), 4u) << "subjects get different orders";
  bool differs = false;
  for (std::size_t s = 0; s < 12; ++s) differs = differs || condition_order(Order::random, 4, s, 42) != condition_order(Order::random, 4, s, 43);
  EXPECT_TRUE(differs) << "another seed, other orders";
}

TEST(Plan, TrialsFollowTheProtocol) {
  test::TempDir dir;
  const ExperimentSpec spec = load_experiment(write_experiment(dir, "order: balanced\nfamiliarisation_s: 30\npractice_s: 20\n"));
  const std::vector<Trial> plan = make_plan(spec);
  ASSERT_EQ(plan.size(), 4u * (1 + 4 * 2));
  // subject 1: familiarisation in its first condition, then practice + measured per condition
  EXPECT_EQ(plan[0].kind, TrialKind::familiarisation);
  EXPECT_EQ(plan[0].limit_s, 30.0);
  EXPECT_EQ(plan[0].condition.label, plan[2].condition.label);
  const std::vector<std::size_t> order = condition_order(Order::balanced, 4, 0, 5);
  for (int c = 0; c < 4; ++c) {
    const Trial& practice = plan[static_cast<std::size_t>(1 + 2 * c)];
    const Trial& measured = plan[static_cast<std::size_t>(2 + 2 * c)];
    EXPECT_EQ(practice.kind, TrialKind::practice);
    EXPECT_EQ(practice.limit_s, 20.0);
    EXPECT_EQ(measured.kind, TrialKind::measured);
    EXPECT_EQ(measured.limit_s, 10.0);
    EXPECT_EQ(measured.order, c + 1);
    EXPECT_EQ(measured.condition.label, spec.conditions[order[static_cast<std::size_t>(c)]].label);
  }
  // one subject's traits for all its trials, fresh noise per trial; file names unique
  std::set<std::uint32_t> noise;
  std::set<std::string> stems;
  for (const Trial& t : plan) {
    EXPECT_EQ(t.subject_seed, plan[t.subject_index * 9].subject_seed);
    noise.insert(t.noise_seed);
    stems.insert(t.file_stem);
  }
  EXPECT_NE(plan[0].subject_seed, plan[9].subject_seed);
  EXPECT_EQ(noise.size(), plan.size());
  EXPECT_EQ(stems.size(), plan.size());
  EXPECT_EQ(plan[2].file_stem.rfind("s1_", 0), 0u) << plan[2].file_stem;
}

TEST(Plan, OverridesReplaceSubjectsAndConditions) {
  test::TempDir dir;
  ExperimentSpec spec = load_experiment(write_experiment(dir, ""));
  override_subjects(spec, 2);
  override_conditions(spec, {"CM3", "T"});
  const std::vector<Trial> plan = make_plan(spec);
  ASSERT_EQ(plan.size(), 4u);
  EXPECT_EQ(plan[3].subject, "2");
  std::set<std::string> labels;
  for (const Trial& t : plan) labels.insert(t.condition.label);
  EXPECT_EQ(labels, (std::set<std::string>{"CM3", "T"}));
  EXPECT_THROW(override_conditions(spec, {"CM9"}), config::Error);
  EXPECT_THROW(override_subjects(spec, 0), config::Error);
}

TEST(Plan, BadFilesNameTheLineAndTheFix) {
  const std::string subject = test::source_path("launch/experiments/subjects/quick.yaml");
  const std::string graph = test::source_path("launch/experiments/trial_rt.yaml");
  const std::string head = "name: t\nsubjects: 2\nvirtual_subject: " + subject + "\ngraph: " + graph + "\n";  // lines 1-4
  struct Case {
    std::string text, needle;
  };
  const Case cases[] = {
      {head + "conditions: [CM0]\nlimt_s: 3\n", "bad.yaml:6:"},                               // a typo
      {head + "conditions: [CM0, CM9]\n", "bad.yaml:5:"},                                      // not a model
      {head + "conditions: [CM1, CM1]\n", "listed twice"},
      {head + "conditions: [CM1]\norder: sideways\n", "bad.yaml:6:"},
      {head + "conditions: [CM1]\nlimit_s: -3\n", "bad.yaml:6:"},
      {"name: t\nsubjects: [a, a]\nconditions: [CM1]\ngraph: " + graph + "\n", "bad.yaml:2:"},
      {"name: t\nsubjects: 2\nconditions: [CM1]\ngraph: " + test::source_path("launch/bridge_rt.yaml") + "\n", "declares no argument"},
      {"name: t\nsubjects: 2\nconditions: [CM1]\ngraph: nowhere.yaml\n", "bad.yaml:4:"},
      {"name: t\nsubjects: 2\nvirtual_subject: nobody.yaml\nconditions: [CM1]\ngraph: " + graph + "\n", "bad.yaml:3:"},
      {head + "conditions: [CM1]\nkind: survey\n", "bad.yaml:6:"},  // neither bridge nor discrimination
  };
  for (const Case& c : cases) {
    const std::string e = error_of(c.text);
    EXPECT_NE(e.find(c.needle), std::string::npos) << c.text << "\n--> " << e;
    EXPECT_NE(e.find("fix:"), std::string::npos) << e;
  }
}

TEST(Plan, ShippedExperimentsLoad) {
  const ExperimentSpec paper = load_experiment(test::source_path("launch/experiments/bridge.yaml"));
  EXPECT_EQ(paper.subjects.size(), 12u);
  EXPECT_EQ(paper.conditions.size(), 4u);
  EXPECT_EQ(paper.limit_s, 180.0);
  const ExperimentSpec quick = load_experiment(test::source_path("launch/experiments/bridge_quick.yaml"));
  EXPECT_TRUE(quick.virtual_subjects());
  // kind: bridge is the default, and may be written
  const test::TempDir dir;
  EXPECT_EQ(load_experiment(write_experiment(dir, "kind: bridge\n")).conditions.size(), 4u);
}

}  // namespace
}  // namespace enact::experiment
