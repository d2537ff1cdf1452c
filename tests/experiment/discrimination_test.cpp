// Discrimination experiments without a graph (graph: false): the shipped example loads and
// runs end to end (through the library and the command line), every trial is recorded with
// its randomised reference interval, an interrupted run resumes to the same files as an
// uninterrupted one, a folder of another experiment is refused, bad files are refused with
// file:line and the fix, and a person's answer comes from the keyboard or a button press.
// On the graph: discrimination_graph_test.cpp.
#include "core/experiment/discrimination.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "core/experiment/results.h"
#include "tests/support/refusal.h"
#include "tests/support/test_util.h"

namespace enact::experiment {
namespace {

class QuietUi final : public RunnerUi {
 public:
  bool start_trial(const Trial&) override { return true; }
  TrialCommand poll(const Trial&) override { return TrialCommand::none; }
  // the keys typed, one per poll (0: none)
  int interval_answer() override {
    if (keys.empty()) return 0;
    const int key = keys.front();
    keys.erase(keys.begin());
    return key;
  }
  std::map<std::string, int> ranking(const std::string&, const std::vector<Condition>&) override { return {}; }
  void progress(const Progress&) override {}
  void note(const std::string& text) override {
    ++notes;
    texts.push_back(text);
  }
  int notes = 0;
  std::vector<std::string> texts;
  std::vector<int> keys;
};

const std::string kExample = "launch/experiments/stiffness_discrimination.yaml";

// the example with 3 subjects and a lighter bootstrap
DiscriminationSpec small_example() {
  DiscriminationSpec spec = load_discrimination(test::source_path(kExample));
  spec.subjects = {"1", "2", "3"};
  spec.bootstrap_replicates = 40;
  return spec;
}

std::vector<std::vector<std::string>> rows_of(const std::string& path) {
  std::istringstream in(test::read_file(path));
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) rows.push_back(cells(line));
  return rows;
}

TEST(Discrimination, TheExampleLoadsAsWritten) {
  EXPECT_TRUE(is_discrimination(test::source_path(kExample)));
  EXPECT_FALSE(is_discrimination(test::source_path("launch/experiments/bridge_quick.yaml")));
  const DiscriminationSpec spec = load_discrimination(test::source_path(kExample));
  EXPECT_EQ(spec.parameter, "stiffness_n_per_m");
  EXPECT_EQ(spec.reference, 600.0);
  ASSERT_EQ(spec.conditions.size(), 2u);
  EXPECT_EQ(spec.observers.weber_fraction.at("CM0"), 0.16);
  EXPECT_EQ(spec.observers.weber_fraction.at("CM1"), 0.12);
  ASSERT_EQ(spec.procedures.size(), 1u);
  EXPECT_EQ(spec.procedures[0].kind, ProcedureSpec::Kind::quest);
  EXPECT_EQ(spec.procedures[0].quest.max_trials, 60);
  EXPECT_EQ(spec.fit.spread, 3.5);
  EXPECT_FALSE(spec.on_graph()) << "graph: false: the observers answer without a graph";
  EXPECT_TRUE(spec.virtual_observers);
  // a paired design: each subject's JND in CM1 is 0.12 / 0.16 of its JND in CM0
  std::map<std::string, std::map<std::string, double>> jnd;
  for (const DiscriminationBlock& b : make_blocks(spec)) jnd[b.subject][b.condition.label] = b.observer.function.threshold;
  EXPECT_EQ(jnd.size(), 12u);
  for (const auto& [subject, by] : jnd) EXPECT_NEAR(by.at("CM1") / by.at("CM0"), 0.75, 1e-12) << subject;
}

TEST(Discrimination, TheDeviceExampleRunsPeopleOnTheTrialGraph) {
  const DiscriminationSpec spec = load_discrimination(test::source_path("launch/experiments/stiffness_discrimination_device.yaml"));
  EXPECT_FALSE(spec.virtual_observers) << "no virtual_observers: people";
  EXPECT_EQ(spec.launch, test::source_path("launch/experiments/trial_rt.yaml"));
  EXPECT_EQ(spec.interval_s, 2.0);
  for (const DiscriminationBlock& b : make_blocks(spec)) EXPECT_TRUE(std::isnan(b.observer.function.threshold)) << "no observer's JND";
}

TEST(Discrimination, TheManifestIsWrittenBeforeTheFirstTrial) {
  const test::TempDir dir;
  const DiscriminationSpec spec = small_example();
  QuietUi ui;
  const DiscriminationRun none = run_discrimination(spec, dir.path(), ui, 1);
  EXPECT_EQ(none.trials_run, 1u);
  const std::string manifest = test::read_file(dir.file("manifest.txt"));
  EXPECT_NE(manifest.find("experiment_fnv1a64: "), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("seed: 7\n"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("analysis: weibull, exponent 3.5"), std::string::npos) << manifest;
  // one line per block with its seed and its observer's JND
  std::size_t blocks = 0;
  for (const DiscriminationBlock& b : make_blocks(spec)) {
    blocks += manifest.find(b.subject + "," + b.condition.label + "," + std::to_string(b.order) + "," + std::to_string(b.seed) + ",") != std::string::npos;
  }
  EXPECT_EQ(blocks, 6u);
  EXPECT_EQ(test::read_file(dir.file("experiment.yaml")), test::read_file(test::source_path(kExample)));
}

TEST(Discrimination, RecordsEveryTrialAndFitsEveryBlock) {
  const test::TempDir dir;
  const DiscriminationSpec spec = small_example();
  QuietUi ui;
  const DiscriminationRun run = run_discrimination(spec, dir.path(), ui);
  EXPECT_FALSE(run.interrupted);
  EXPECT_EQ(run.trials_run, 3u * 2u * 60u);
  for (const std::string& t : ui.texts) EXPECT_EQ(t.find("warning"), std::string::npos) << "60 trials a block are enough: " << t;
  const auto trials = rows_of(run.trials);
  ASSERT_EQ(trials.size(), 360u);
  std::map<std::string, int> interval_count;
  for (const auto& r : trials) {
    ASSERT_EQ(r.size(), 13u);
    EXPECT_EQ(r[12], "nan") << "no graph: no response time";
    EXPECT_EQ(r[5], "stiffness_n_per_m");
    EXPECT_NEAR(std::stod(r[7]), 600.0 + std::stod(r[8]), 1e-6) << "comparison = reference + level";
    EXPECT_TRUE(r[9] == "1" || r[9] == "2");
    EXPECT_EQ(r[11] == "1", r[10] != r[9]) << "correct: the comparison's (stiffer) interval was named";
    interval_count[r[9]] += 1;
  }
  // the reference's interval is drawn at random: 360 trials, each near 180 (4 SDs of 9.5)
  EXPECT_NEAR(interval_count["1"], 180, 38);
  const auto summary = rows_of(run.summary);
  ASSERT_EQ(summary.size(), 6u);
  for (const auto& r : summary) {
    ASSERT_EQ(r.size(), 13u);
    const double jnd = std::stod(r[4]), low = std::stod(r[5]), high = std::stod(r[6]);
    EXPECT_EQ(r[3], "60");
    EXPECT_LT(low, jnd);
    EXPECT_GT(high, jnd);
    EXPECT_NEAR(std::stod(r[9]), jnd / 600.0, 1e-6) << "Weber fraction = JND / reference";
    // the lapse to its stated precision: a fit at the bound 0 prints 0, not 1e-15
    const double lapse = std::stod(r[10]);
    EXPECT_TRUE(lapse == 0.0 || lapse >= kLapsePrecision) << r[10];
    EXPECT_NEAR(lapse / kLapsePrecision, std::round(lapse / kLapsePrecision), 1e-6) << r[10];
  }
}

// a block fitted from fewer answers than a fit can rest on is warned about, with the fix
TEST(Discrimination, AFitOfTooFewTrialsIsWarnedAbout) {
  const test::TempDir dir;
  const std::string path = dir.file("short.yaml");
  test::write_file(path, R"(kind: discrimination
subjects: 1
conditions: [CM0]
parameter: stiffness_n_per_m
reference: 600
graph: false
procedures:
  - {label: staircase, kind: staircase, start: 300, step_sizes: [0.2, 0.1], reversals: 8, max_trials: 6}
virtual_observers: {weber_fraction: 0.15}
analysis: {shape: weibull, exponent: 3.5, bootstrap: 0}
)");
  QuietUi ui;
  const DiscriminationRun run = run_discrimination(load_discrimination(path), dir.file("out"), ui);
  ASSERT_EQ(rows_of(run.summary).size(), 1u);
  std::string warned;
  for (const std::string& t : ui.texts) warned += t.find("warning") != std::string::npos ? t : "";
  EXPECT_NE(warned.find("warning: subject 1, CM0: its fit rests on 6 trials, fewer than 30"), std::string::npos) << warned;
  EXPECT_NE(warned.find("fix: give the procedures more trials"), std::string::npos) << warned;
  // the script says so too
  const std::string counts = dir.file("counts.csv");
  test::write_file(counts, "level,trials,correct\n100,3,2\n200,3,3\n");
  const test::RunResult fit = test::run("/usr/bin/python3 " + test::source_path("scripts/psychophysics.py") + " fit " + counts + " --shape weibull");
  EXPECT_EQ(fit.exit_code, 0) << fit.err;
  EXPECT_NE(fit.err.find("the fit rests on 6 trials, fewer than 30"), std::string::npos) << fit.err;
}

TEST(Discrimination, AnInterruptedRunResumesToTheSameFiles) {
  const test::TempDir whole, parts;
  const DiscriminationSpec spec = small_example();
  QuietUi ui;
  run_discrimination(spec, whole.path(), ui);
  // stopped three times, in the middle of blocks, then finished
  std::size_t run = 0;
  for (std::size_t stop : {25u, 70u, 100u}) {
    const DiscriminationRun part = run_discrimination(spec, parts.path(), ui, stop);
    EXPECT_TRUE(part.interrupted);
    EXPECT_EQ(part.trials_run, stop);
    run += part.trials_run;
    EXPECT_FALSE(test::read_file_or_empty(parts.file("summary.csv")).size()) << "no summary before the end";
  }
  const DiscriminationRun last = run_discrimination(spec, parts.path(), ui);
  EXPECT_FALSE(last.interrupted);
  EXPECT_EQ(run + last.trials_run, 360u);
  EXPECT_EQ(test::read_file(parts.file("trials.csv")), test::read_file(whole.file("trials.csv")));
  EXPECT_EQ(test::read_file(parts.file("summary.csv")), test::read_file(whole.file("summary.csv")));
  // run again: nothing to do
  const DiscriminationRun again = run_discrimination(spec, parts.path(), ui);
  EXPECT_EQ(again.trials_run, 0u);
  EXPECT_EQ(again.blocks_done_before, 6u);
}

TEST(Discrimination, AFolderOfAnotherRunIsRefused) {
  const test::TempDir dir, other;
  QuietUi ui;
  DiscriminationSpec spec = small_example();
  run_discrimination(spec, dir.path(), ui, 10);
  // another experiment file
  const std::string changed = other.file("changed.yaml");
  test::write_file(changed, test::read_file(test::source_path(kExample)) + "\n# changed\n");
  DiscriminationSpec another = load_discrimination(changed);
  const std::string refused = test::error_of([&] { run_discrimination(another, dir.path(), ui); });
  EXPECT_NE(refused.find("another plan"), std::string::npos) << refused;
  // fewer subjects (--subjects)
  DiscriminationSpec fewer = spec;
  fewer.subjects.pop_back();
  const std::string shorter = test::error_of([&] { run_discrimination(fewer, dir.path(), ui); });
  EXPECT_NE(shorter.find("another plan"), std::string::npos) << shorter;
  // the same file, but trials.csv holds levels these procedures would not ask for
  DiscriminationSpec moved = spec;
  moved.procedures[0].quest.guess_level = 50.0;
  const std::string replayed = test::error_of([&] { run_discrimination(moved, dir.path(), ui); });
  EXPECT_NE(replayed.find("another run"), std::string::npos) << replayed;
}

TEST(Discrimination, InterleavedStaircasesAndConstantStimuliRunTogether) {
  const test::TempDir dir;
  const std::string path = dir.file("mix.yaml");
  test::write_file(path, R"(kind: discrimination
subjects: 2
conditions: [CM0]
parameter: damping_n_s_per_m
reference: 2.0
graph: false
procedures:
  - {label: ascending, kind: staircase, start: 0.05, step_sizes: [0.2, 0.1], reversals: 8}
  - {label: descending, kind: staircase, start: 1.0, down: 3, step_sizes: [0.2, 0.1], reversals: 8}
  - {label: fixed, kind: constant, levels: [0.1, 0.2, 0.4, 0.8], repetitions: 5}
virtual_observers: {weber_fraction: 0.15, lapse: 0.0}
analysis: {shape: gaussian, bootstrap: 0}
)");
  const DiscriminationSpec spec = load_discrimination(path);
  QuietUi ui;
  const DiscriminationRun run = run_discrimination(spec, dir.file("out"), ui);
  std::map<std::string, int> per_procedure;
  std::vector<std::string> first_ten;
  for (const auto& r : rows_of(run.trials)) {
    per_procedure[r[3]] += r[0] == "1";
    if (r[0] == "1" && first_ten.size() < 10) first_ten.push_back(r[3]);
  }
  EXPECT_EQ(per_procedure["fixed"], 20) << "4 levels x 5";
  EXPECT_GE(per_procedure["ascending"], 8) << "at least its 8 reversals";
  EXPECT_GE(per_procedure["descending"], 8);
  EXPECT_EQ(std::set<std::string>(first_ten.begin(), first_ten.end()).size(), 3u) << "interleaved from the start";
  const auto summary = rows_of(run.summary);
  ASSERT_EQ(summary.size(), 2u);
  EXPECT_EQ(summary[0][7], "nan") << "no bootstrap asked";
}

std::string refusal(const std::string& text) {
  return test::error_of_file("bad.yaml", text, [](const std::string& path) { load_discrimination(path); });
}

const std::string kGood = "kind: discrimination\nsubjects: 2\nconditions: [CM0, CM1]\nparameter: stiffness_n_per_m\nreference: 600\n";
const std::string kQuest = "procedures:\n  - {kind: quest, guess: 90}\n";
const std::string kObservers = "virtual_observers: {weber_fraction: 0.15}\n";

TEST(Discrimination, BadFilesAreRefusedWithTheLineAndTheFix) {
  const std::string fast = "graph: false\n";
  EXPECT_EQ(refusal(kGood + kQuest + kObservers + fast), "");
  struct Case {
    std::string text, says, line;
  };
  const std::vector<Case> cases{
      {"kind: discrimination\nsubjects: 2\nconditions: [CM0]\nparameter: mass_kg\nreference: 1\n" + kQuest + kObservers + fast, "not a numeric live parameter", ":4:"},
      {kGood + "procedures:\n  - {kind: bisection}\n" + kObservers + fast, "is not quest, staircase or constant", ":7:"},
      {kGood + "procedures:\n  - {kind: staircase, start: 100, step_sizes: [0.1, -1]}\n" + kObservers + fast, "step sizes must be > 0", ":7:"},
      {kGood + "procedures:\n  - {kind: quest, guess: 90}\n  - {kind: quest, guess: 50}\n" + kObservers + fast, "used twice", ":8:"},
      {kGood + kQuest + fast, "runs virtual observers only", ":8:"},
      {kGood + kQuest + kObservers, "names its trials' graph", ":1:"},
      {kGood + kQuest + kObservers + "graph: nowhere.yaml\n", "no launch file", ":9:"},
      {kGood + kQuest + kObservers + fast + "interval_s: 0\n", "interval_s", ":10:"},
      {kGood + kQuest + "virtual_observers: {weber_fraction: [0.1, 0.2, 0.3]}\n" + fast, "one per condition", ":8:"},
      {kGood + kQuest + kObservers + "analysis: {shape: gaussian, exponent: 3}\n" + fast, "has no exponent", ":9:"},
      {kGood + kQuest + kObservers + "stop_rule: 3\n" + fast, "stop_rule", ":9:"},
  };
  for (const Case& c : cases) {
    const std::string e = refusal(c.text);
    EXPECT_NE(e.find(c.says), std::string::npos) << e;
    EXPECT_NE(e.find("bad.yaml" + c.line), std::string::npos) << e;
    EXPECT_NE(e.find("fix:"), std::string::npos) << e;
  }
}

TEST(Discrimination, APersonAnswersWithAKeyOrAButtonPress) {
  const DiscriminationSpec spec = small_example();
  const std::vector<DiscriminationBlock> blocks = make_blocks(spec);
  Presentation trial;
  trial.block = &blocks[0];
  QuietUi ui;
  PersonAnswers person(ui);
  // nothing typed, nothing pressed: no answer yet
  EXPECT_EQ(person.answer(trial, 0), 0);
  ui.keys = {2};
  EXPECT_EQ(person.answer(trial, 0), 2) << "the key typed";
  // button 0 names interval 1, button 1 interval 2, when pressed, not while held
  EXPECT_EQ(person.answer(trial, 1u), 1);
  EXPECT_EQ(person.answer(trial, 1u), 0) << "held";
  EXPECT_EQ(person.answer(trial, 0), 0) << "released";
  EXPECT_EQ(person.answer(trial, 2u), 2);
  // a button held before the question does not answer it
  PersonAnswers late(ui);
  EXPECT_EQ(late.answer(trial, 1u), 0);
}

TEST(Discrimination, AnObserverAnswersAsItsPsychometricFunctionSays) {
  const DiscriminationSpec spec = small_example();
  const std::vector<DiscriminationBlock> blocks = make_blocks(spec);
  ObserverAnswers observer;
  Presentation trial;
  trial.block = &blocks[0];
  // far above its JND it names the comparison's interval, but for its lapses (2 %)
  int correct = 0;
  for (std::size_t i = 0; i < 400; ++i) {
    trial.trial = i;
    trial.level = 10.0 * blocks[0].observer.function.threshold;
    trial.reference_interval = 1 + static_cast<int>(i % 2);
    const int chosen = observer.answer(trial, 0);
    EXPECT_EQ(chosen, blocks[0].observer.chosen_interval(i, trial.level, trial.larger_interval()));
    correct += chosen == trial.larger_interval();
  }
  EXPECT_GT(correct, 380) << "psi = 0.5 + (1 - 0.5 - lapse) F: 98 % of 400";
}

TEST(Discrimination, TheCommandLineRunsTheExampleEndToEnd) {
  const test::TempDir dir;
  const std::string command = std::string(ENACT_CLI) + " experiment " + test::source_path(kExample) + " --subjects 2 --out " + dir.file("out");
  const test::RunResult r = test::run(command);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("summary: "), std::string::npos) << r.err;
  EXPECT_EQ(rows_of(dir.file("out/trials.csv")).size(), 2u * 2u * 60u);
  EXPECT_EQ(rows_of(dir.file("out/summary.csv")).size(), 4u);
  // the figures from it, with scipy, by the command it prints: it fits as summary.csv does
  const std::size_t hint = r.err.find("figures: ");
  ASSERT_NE(hint, std::string::npos) << r.err;
  const std::string plot_command = r.err.substr(hint + 9, r.err.find('\n', hint) - hint - 9);
  EXPECT_NE(plot_command.find(" --shape weibull --exponent 3.5 --max-lapse 0.06"), std::string::npos) << plot_command;
  const test::RunResult plot = test::run(plot_command);
  EXPECT_EQ(plot.exit_code, 0) << plot.err;
  EXPECT_NE(test::read_file_or_empty(dir.file("out/figures/s1_CM0.png")), "");
  // the group statistics: both subjects in both conditions, one pair
  const test::RunResult group = test::run("/usr/bin/python3 " + test::source_path("scripts/psychophysics.py") + " group " + dir.file("out/summary.csv"));
  EXPECT_EQ(group.exit_code, 0) << group.err;
  EXPECT_NE(group.out.find("\"CM0-CM1\": {\n   \"subjects\": 2"), std::string::npos) << group.out;
  const test::RunResult plan = test::run(std::string(ENACT_CLI) + " experiment " + test::source_path(kExample) + " --plan");
  EXPECT_EQ(plan.exit_code, 0) << plan.err;
  EXPECT_NE(plan.out.find("stiffness_n_per_m around 600"), std::string::npos) << plan.out;
}

}  // namespace
}  // namespace enact::experiment
