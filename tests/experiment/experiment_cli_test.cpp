// `enact experiment` end to end on real graphs (short trials): each trial recorded, its
// metrics in results.csv equal to `enact metrics` replaying the recording, an interrupted
// run resumed without running a completed trial again, simulated time (the same trials, tick
// for tick, as real time without a missed deadline), the distributed graph, people
// prompted and asked for their ranking, bad input refused.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/record/reader.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/task_event.pb.h"
#include "tests/cli/cli_support.h"
#include "tests/experiment/experiment_run.h"
#include "tests/support/recorded_ticks.h"
#include "tests/support/test_util.h"

namespace enact::test {
namespace {

using Clock = std::chrono::steady_clock;

// an experiment file in `dir` on the shipped trial graphs
std::string experiment_file(const TempDir& dir, const std::string& body) {
  const std::string path = dir.file("exp.yaml");
  write_file(path, "name: tiny\nseed: 3\n" + body);
  return path;
}

std::string virtual_tiny(const TempDir& dir, const std::string& conditions, double limit_s, const std::string& graph = "trial_rt.yaml") {
  return experiment_file(dir, "subjects: 1\nvirtual_subject: " + source_path("launch/experiments/subjects/quick.yaml") + "\nconditions: [" +
                                  conditions + "]\norder: balanced\nlimit_s: " + std::to_string(limit_s) +
                                  "\ngraph: " + source_path("launch/experiments/" + graph) + "\n");
}

// enact metrics --json agrees with itself (replay = live) and with a results.csv row
void expect_metrics_agree(const std::string& recording, const std::vector<std::string>& row) {
  const RunResult m = enact("metrics --json " + recording);
  ASSERT_EQ(m.exit_code, 0) << m.out << m.err;
  EXPECT_EQ(json_value(m.out, "agree"), "true") << m.out;
  EXPECT_EQ(json_value(m.out, "first_state_seq"), "1") << "recorded from the first tick";
  EXPECT_EQ(json_value(m.out, "falls"), row[3]);
  EXPECT_NEAR(std::stod(json_value(m.out, "time_total_s")), std::stod(row[4]), 1e-6);
  EXPECT_NEAR(std::stod(json_value(m.out, "time_out_s")), std::stod(row[5]), 1e-6);
  EXPECT_EQ(json_value(m.out, "completed"), row[7] == "1" ? "true" : "false");
}

std::int64_t mtime_ns(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return -1;
  return static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec;
}

// the graph clock a recording says made it (its enact.graph metadata)
std::string recorded_clock(const std::string& recording) {
  record::Reader r(recording);
  const auto graph = r.metadata("enact.graph");
  return graph.count("clock") ? graph.at("clock") : "";
}

TEST(ExperimentCli, EachTrialIsRecordedAndItsMetricsAreTheReplaysOnEitherClock) {
  for (const std::string clock : {"real", "simulated"}) {
    SCOPED_TRACE(clock + " time");
    TempDir dir;
    const RunResult r = enact("experiment " + virtual_tiny(dir, "CM0, CM1", 8.0) + " --clock " + clock + " --out " + dir.file("out"));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const auto rows = csv_rows(dir.file("out/results.csv"));
    ASSERT_EQ(rows.size(), 3u) << r.err;
    EXPECT_EQ(rows[0], (std::vector<std::string>{"subject", "condition", "order", "falls", "time_total_s", "time_out_s", "ratio", "completed", "missed_deadlines"}));
    // Williams' first row for two conditions: CM0 then CM1
    EXPECT_EQ(rows[1][0], "1");
    EXPECT_EQ(rows[1][1], "CM0");
    EXPECT_EQ(rows[1][2], "1");
    EXPECT_EQ(rows[2][1], "CM1");
    EXPECT_EQ(rows[2][2], "2");
    for (std::size_t i = 1; i < rows.size(); ++i) {
      const double total = std::stod(rows[i][4]);
      EXPECT_TRUE(rows[i][7] == "1" || std::abs(total - 8.0) < 0.01) << "completed, or stopped at the limit: " << total;
      if (clock == "simulated") EXPECT_EQ(rows[i][8], "0") << "no deadline to miss in simulated time";
      const std::string recording = dir.file("out/trials/s1_" + rows[i][1] + "_measured.mcap");
      expect_metrics_agree(recording, rows[i]);
      EXPECT_EQ(recorded_clock(recording), clock);
      const RunResult resim = enact("resim " + recording);
      EXPECT_EQ(resim.exit_code, 0) << resim.out << resim.err;
      EXPECT_NE(resim.out.find(clock + " time"), std::string::npos) << resim.out;
    }
    EXPECT_NE(read_file(dir.file("out/trials/s1_CM0_measured.log")).find("logger: closed"), std::string::npos) << "the nodes' output is in the log";
    EXPECT_NE(r.err.find("2 trials run"), std::string::npos) << r.err;
  }
}

TEST(ExperimentCli, InterruptedRunResumesWithoutRunningCompletedTrials) {
  TempDir dir;
  const std::string file = virtual_tiny(dir, "CM1, CM3", 6.0);
  const std::string results = dir.file("out/results.csv");
  std::vector<std::string> first_row;
  std::int64_t first_mtime = 0;
  {
    Experiment run(dir, {file, "--out", dir.file("out")});
    ASSERT_TRUE(run.wait_for("subject 1, CM1", 1, 60.0)) << run.terminal();
    run.signal(SIGINT);
    EXPECT_EQ(run.wait_exit(30.0), 130) << run.terminal();
    EXPECT_NE(run.terminal().find("run the same command again to resume"), std::string::npos) << run.terminal();
    const auto rows = csv_rows(results);
    ASSERT_EQ(rows.size(), 2u) << "the first trial is kept, the interrupted one is not";
    first_row = rows[1];
    first_mtime = mtime_ns(dir.file("out/trials/s1_CM1_measured.mcap"));
  }
  const RunResult again = enact("experiment " + file + " --out " + dir.file("out"));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("1 trials run, 1 done before"), std::string::npos) << again.err;
  const auto rows = csv_rows(results);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1], first_row);
  EXPECT_EQ(rows[2][1], "CM3");
  EXPECT_EQ(mtime_ns(dir.file("out/trials/s1_CM1_measured.mcap")), first_mtime) << "the completed trial did not run again";
  expect_metrics_agree(dir.file("out/trials/s1_CM3_measured.mcap"), rows[2]);
  // done: a third run has nothing left
  const RunResult third = enact("experiment " + file + " --out " + dir.file("out"));
  EXPECT_EQ(third.exit_code, 0);
  EXPECT_NE(third.err.find("0 trials run, 2 done before"), std::string::npos) << third.err;
  // another plan in the same folder is refused
  const RunResult other = enact("experiment " + file + " --conditions CM0,CM2 --out " + dir.file("out"));
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.err.find("plan.csv: this folder holds a run of another plan"), std::string::npos) << other.err;
  // and so is the same plan on another clock
  const RunResult simulated = enact("experiment " + file + " --clock simulated --out " + dir.file("out"));
  EXPECT_EQ(simulated.exit_code, 1);
  EXPECT_NE(simulated.err.find("clock.txt: this folder holds a run of another plan (--clock differs)"), std::string::npos) << simulated.err;
}

TEST(ExperimentCli, ARealTimeTrialIsItsSimulatedTimeTwinTickForTickUntilADeadlineIsMissed) {
  // the same trial (subject, seeds, model) on the co-located graph in simulated time and in
  // real time: every tick's device position and force are the same, bit for bit, as long as
  // the real-time loop missed no deadline. A model (or device, or subject) whose time came
  // from the wall clock differs from the first ticks on (and its stamps never step by exactly
  // a period). A loaded machine may miss deadlines: each run is compared up to its first
  // miss, and repeated while that leaves less than half a second; on a machine too busy for
  // that, 50 ms (250 ticks) still shows a wall-clock time, which differs within a few ticks
  constexpr std::int64_t kPeriod_ns = 200'000;  // 5 kHz
  constexpr std::size_t kEnough = 2500, kAtLeast = 250;
  TempDir dir;
  const std::string file = virtual_tiny(dir, "CM1", 1.5);
  const RunResult sim = enact("experiment " + file + " --clock simulated --out " + dir.file("sim"));
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const std::vector<RecordedTick> twin = recorded_ticks(dir.file("sim/trials/s1_CM1_measured.mcap"));
  ASSERT_EQ(twin.size(), 7500u) << "1.5 s at 5 kHz, every tick recorded";
  ASSERT_EQ(ticks_before_first_miss(twin, kPeriod_ns), twin.size()) << "simulated time: every deadline, every force";
  std::size_t compared = 0;
  for (int attempt = 0; attempt < 5 && compared < kEnough; ++attempt) {
    const std::string out = dir.file("rt" + std::to_string(attempt));
    const RunResult real = enact("experiment " + file + " --out " + out);
    ASSERT_EQ(real.exit_code, 0) << real.err;
    EXPECT_EQ(recorded_clock(out + "/trials/s1_CM1_measured.mcap"), "real");
    const std::vector<RecordedTick> ticks = recorded_ticks(out + "/trials/s1_CM1_measured.mcap");
    const std::size_t clean = std::min(ticks_before_first_miss(ticks, kPeriod_ns), twin.size());
    for (std::size_t i = 0; i < clean; ++i) {
      ASSERT_EQ(std::memcmp(ticks[i].position, twin[i].position, sizeof twin[i].position), 0) << "position at tick " << i + 1 << " (run " << attempt + 1 << ")";
      ASSERT_EQ(std::memcmp(ticks[i].force, twin[i].force, sizeof twin[i].force), 0) << "force at tick " << i + 1 << " (run " << attempt + 1 << ")";
    }
    std::printf("[ twin ] real-time run %d: %zu ticks before its first missed deadline, each equal to its simulated twin\n", attempt + 1, clean);
    compared = std::max(compared, clean);
  }
  EXPECT_GE(compared, kAtLeast) << "no real-time run held its deadlines for 50 ms, or its ticks' times are not its deadlines";
}

// the distributed graph in simulated time: the clock master ticks in lock-step (the next
// tick once the simulator's answer and the pins of the frame it sent are in), so every tick
// is recorded, stamped a period apart, and a run of the trial is the co-located graph's run
// of it, bit for bit, the virtual subject feeling the pins rise tick by tick from the motion
// the tactile driver sends (a subject that felt each frame's pins held until the next frame,
// or at another tick, moves differently within a few frames); a second run is the same run
TEST(ExperimentCli, TheDistributedGraphInSimulatedTimeIsTheColocatedGraphsTwinEveryTime) {
  constexpr std::int64_t kPeriod_ns = 200'000;  // 5 kHz
  constexpr double kLimit_s = 3.0;
  TempDir dir;
  const RunResult colocated = enact("experiment " + virtual_tiny(dir, "CM1", kLimit_s) + " --clock simulated --out " + dir.file("rt"));
  ASSERT_EQ(colocated.exit_code, 0) << colocated.err;
  const std::vector<RecordedTick> twin = recorded_ticks(dir.file("rt/trials/s1_CM1_measured.mcap"));
  ASSERT_EQ(ticks_before_first_miss(twin, kPeriod_ns), twin.size());
  const std::string file = virtual_tiny(dir, "CM1", kLimit_s, "trial.yaml");
  for (const std::string out : {"a", "b"}) {
    SCOPED_TRACE("run " + out);
    const RunResult r = enact("experiment " + file + " --clock simulated --out " + dir.file(out));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto rows = csv_rows(dir.file(out + "/results.csv"));
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[1][8], "0") << "no deadline to miss in simulated time";
    const std::string recording = dir.file(out + "/trials/s1_CM1_measured.mcap");
    EXPECT_EQ(recorded_clock(recording), "simulated");
    expect_metrics_agree(recording, rows[1]);
    const std::vector<RecordedTick> ticks = recorded_ticks(recording);
    const bool completed = rows[1][7] == "1";
    if (!completed) EXPECT_EQ(ticks.size(), 15000u) << "3 s at 5 kHz, every tick recorded";
    EXPECT_EQ(ticks_before_first_miss(ticks, kPeriod_ns), ticks.size()) << "every tick a period after the last, every force recorded";
    const std::string log = read_file(dir.file(out + "/trials/s1_CM1_measured.log"));
    EXPECT_NE(log.find("started ffd"), std::string::npos) << "the distributed nodes ran";
    EXPECT_NE(log.find("verdict: simulated time"), std::string::npos) << log;
    std::smatch felt;
    ASSERT_TRUE(std::regex_search(log, felt, std::regex("the virtual subject felt ([0-9]+) pin states from tactile \\(tactile/shown\\); frames whose pins did not come in time: ([0-9]+)"))) << log;
    EXPECT_GT(std::stoi(felt[1].str()), 10) << log;
    EXPECT_EQ(felt[2].str(), "0") << log;
    ASSERT_EQ(ticks.size(), twin.size());
    for (std::size_t i = 0; i < ticks.size(); ++i) {
      ASSERT_EQ(std::memcmp(ticks[i].position, twin[i].position, sizeof ticks[i].position), 0) << "position at tick " << i + 1;
      ASSERT_EQ(std::memcmp(ticks[i].force, twin[i].force, sizeof ticks[i].force), 0) << "force at tick " << i + 1;
    }
    std::printf("[ twin ] run %s: %zu ticks of the distributed graph equal to the co-located graph's\n", out.c_str(), ticks.size());
  }
}

// a user's own scene (two boxes, no task) as an experiment: the trial graph takes it from
// launch_args, every trial runs to its limit (nothing to complete) and is recorded on that
// scene, and its replay agrees with the live run
TEST(ExperimentCli, AUsersOwnSceneRunsAsAnExperiment) {
  TempDir dir;
  const std::string scene = source_path("launch/scenes/two_boxes.yaml");
  const std::string file = experiment_file(dir, "subjects: 1\nvirtual_subject: " + source_path("launch/experiments/subjects/quick.yaml") +
                                                    "\nconditions: [CM1]\norder: balanced\nlimit_s: 1.0\ngraph: " + source_path("launch/experiments/trial_rt.yaml") +
                                                    "\nlaunch_args: {scene: " + scene + "}\n");
  const RunResult r = enact("experiment " + file + " --clock simulated --out " + dir.file("out"));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto rows = csv_rows(dir.file("out/results.csv"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1][7], "0") << "a scene without a task has nothing to complete";
  EXPECT_NE(r.err.find("subject 1, CM1 (measured 1): time 1.00 s (no task in this scene: no falls or completion to count)"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("falls 0"), std::string::npos) << r.err;
  EXPECT_NEAR(std::stod(rows[1][4]), 1.0, 1e-3) << "the trial ran to its limit";
  // recorded on the user's scene: its parameters name the file, 1 s of ticks at 5 kHz
  const std::string recording = dir.file("out/trials/s1_CM1_measured.mcap");
  record::Reader reader(recording);
  bool on_scene = false;
  for (const auto& [name, value] : reader.metadata("enact.params")) on_scene = on_scene || (name.ends_with(".scene") && value.find("two_boxes.yaml") != std::string::npos);
  EXPECT_TRUE(on_scene) << "the trial graph was not given the scene";
  int states = 0;
  reader.for_each([&](const record::Message& m) {
    states += m.topic == "ffd/state";
    return true;
  });
  EXPECT_EQ(states, 5000);
  const RunResult resim = enact("resim " + recording);
  EXPECT_EQ(resim.exit_code, 0) << resim.out << resim.err;
  EXPECT_NE(resim.out.find("identical: every force and every pin frame"), std::string::npos) << resim.out;
  EXPECT_NE(resim.out.find("no task in this scene: no falls or completion to count"), std::string::npos) << resim.out;
  EXPECT_EQ(resim.out.find("task: falls"), std::string::npos) << resim.out;
}

// the second shipped experiment (contour following on the ridge: a height map, its task line
// in the scene, its scene given by launch_args with $(dirname)), one subject and one
// condition in simulated time: run, recorded, completed, its metrics its replay's
TEST(ExperimentCli, TheShippedRidgeExperimentRunsEndToEnd) {
  TempDir dir;
  const RunResult r = enact("experiment " + source_path("launch/experiments/ridge.yaml") + " --subjects 1 --conditions CM1 --clock simulated --out " + dir.file("out"));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto rows = csv_rows(dir.file("out/results.csv"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1][1], "CM1");
  EXPECT_EQ(rows[1][7], "1") << "the baseline subject follows the crest to its end with CM1's pins";
  const double total_s = std::stod(rows[1][4]);
  EXPECT_GT(total_s, 3.0) << "49 mm of crest at about 10 mm/s";
  EXPECT_LT(total_s, 90.0);
  const std::string recording = dir.file("out/trials/s1_CM1_measured.mcap");
  record::Reader reader(recording);
  bool on_ridge = false;
  for (const auto& [name, value] : reader.metadata("enact.params")) on_ridge = on_ridge || (name.ends_with(".scene") && value.ends_with("/scenes/ridge.yaml"));
  EXPECT_TRUE(on_ridge) << "the trial graph was not given the ridge scene";
  expect_metrics_agree(recording, rows[1]);
  const RunResult resim = enact("resim " + recording);
  EXPECT_EQ(resim.exit_code, 0) << resim.out << resim.err;
  EXPECT_NE(resim.out.find("identical: every force and every pin frame"), std::string::npos) << resim.out;
}

TEST(ExperimentCli, DistributedGraphRunsTheTrials) {
  TempDir dir;
  const RunResult r = enact("experiment " + virtual_tiny(dir, "CM1", 5.0, "trial.yaml") + " --out " + dir.file("out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = csv_rows(dir.file("out/results.csv"));
  ASSERT_EQ(rows.size(), 2u);
  expect_metrics_agree(dir.file("out/trials/s1_CM1_measured.mcap"), rows[1]);
  const std::string log = read_file(dir.file("out/trials/s1_CM1_measured.log"));
  EXPECT_NE(log.find("started ffd"), std::string::npos) << "the distributed nodes ran";
  // the subject in enact-ffd felt the pins enact-tactile showed
  std::smatch felt;
  ASSERT_TRUE(std::regex_search(log, felt, std::regex("the virtual subject felt ([0-9]+) pin states from tactile"))) << log;
  EXPECT_GT(std::stoi(felt[1].str()), 100) << "about 100 a second for 5 s";
}

// a trial's graph is a named graph like any other: watched and adjusted while it runs
TEST(ExperimentCli, ATrialCanBeWatchedAndAdjustedLiveByItsName) {
  TempDir dir;
  setenv("ENACT_REGISTRY", dir.file("registry").c_str(), 1);
  Experiment run(dir, {virtual_tiny(dir, "CM1", 10.0), "--out", dir.file("out")});
  // EXPERIMENT/SUBJECT_CONDITION
  const auto end = Clock::now() + std::chrono::seconds(60);
  RunResult list;
  while (Clock::now() < end && (list = enact("graph list")).out.find("tiny/1_CM1") == std::string::npos) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_NE(list.out.find("tiny/1_CM1"), std::string::npos) << list.out << run.terminal();
  const RunResult set = enact("param set sim.stiffness_n_per_m 600 --graph tiny/1_CM1");
  EXPECT_EQ(set.exit_code, 0) << set.out << set.err;
  EXPECT_NE(set.out.find("applied"), std::string::npos) << set.out;
  const RunResult state = enact("topic echo task/state --once --graph tiny/1_CM1");
  EXPECT_EQ(state.exit_code, 0) << state.err;
  EXPECT_NE(state.out.find("model: \"CM1\""), std::string::npos) << state.out;
  EXPECT_EQ(run.wait_exit(60.0), 0) << run.terminal();
  // the change is in the trial's recording, acknowledged
  record::Reader reader(dir.file("out/trials/s1_CM1_measured.mcap"));
  int acks = 0;
  reader.for_each([&](const record::Message& m) {
    acks += m.topic == "param/ack";
    return true;
  });
  EXPECT_EQ(acks, 1);
  EXPECT_NE(enact("graph list").out.find("no graph running"), std::string::npos);
}

TEST(ExperimentCli, PeopleArePromptedAndRankTheConditions) {
  // a "person": the scripted hand walking the bridge, on simulated devices
  TempDir dir;
  const std::string file = experiment_file(dir, "subjects: [P1]\nconditions: [CM1, CM3]\norder: balanced\nlimit_s: 3\ngraph: " +
                                                    source_path("launch/experiments/trial_rt.yaml") + "\nlaunch_args: {hand_path: " +
                                                    source_path("launch/paths/bridge_walk.csv") + "}\n");
  Experiment run(dir, {file, "--out", dir.file("out")});
  ASSERT_TRUE(run.wait_for("next: subject P1, condition CM1", 1, 30.0)) << run.terminal();
  run.type("\nr\n");  // start; then, during the trial, the subject was put back at the start
  ASSERT_TRUE(run.wait_for("next: subject P1, condition CM3", 1, 30.0)) << run.terminal();
  run.type("\n");
  ASSERT_TRUE(run.wait_for("rank of each condition", 1, 30.0)) << run.terminal();
  run.type("2 1\n");
  ASSERT_EQ(run.wait_exit(30.0), 0) << run.terminal();
  EXPECT_EQ(csv_rows(dir.file("out/results.csv")).size(), 3u);
  const auto ranks = csv_rows(dir.file("out/ranking.csv"));
  ASSERT_EQ(ranks.size(), 3u);
  EXPECT_EQ(ranks[1], (std::vector<std::string>{"P1", "CM1", "2"}));
  EXPECT_EQ(ranks[2], (std::vector<std::string>{"P1", "CM3", "1"}));
  // the reset is in the first trial's recording, with the trial's start and condition
  record::Reader reader(dir.file("out/trials/sP1_CM1_measured.mcap"));
  std::vector<msgs::TaskEvent::Kind> kinds;
  msgs::TaskEvent e;
  reader.for_each([&](const record::Message& m) {
    if (m.topic == "task/event" && e.ParseFromArray(m.data.data(), static_cast<int>(m.data.size())) && e.subject() == "P1") kinds.push_back(e.kind());
    return true;
  });
  EXPECT_EQ(kinds, (std::vector<msgs::TaskEvent::Kind>{msgs::TaskEvent::CONDITION, msgs::TaskEvent::TRIAL_START, msgs::TaskEvent::RESET}));
}

TEST(ExperimentCli, BadInputIsRefused) {
  TempDir dir;
  const std::string file = experiment_file(dir, "subjects: 1\nconditions: [CM1]\nlimit_s: 3\ngraph: nowhere.yaml\n");
  const RunResult r = enact("experiment " + file);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("exp.yaml:6:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fix:"), std::string::npos) << r.err;
  const RunResult conditions = enact("experiment " + virtual_tiny(dir, "CM1", 3.0) + " --conditions CM1,XX --plan");
  EXPECT_EQ(conditions.exit_code, 1);
  EXPECT_NE(conditions.err.find("XX"), std::string::npos) << conditions.err;
  EXPECT_EQ(enact("experiment").exit_code, 2);
  EXPECT_EQ(enact("experiment " + virtual_tiny(dir, "CM1", 3.0) + " --clock sometimes --plan").exit_code, 2);
  // the distributed graph with simulated devices runs in simulated time too (its clock master
  // ticks in lock-step): planned, not refused
  const RunResult distributed = enact("experiment " + virtual_tiny(dir, "CM1", 3.0, "trial.yaml") + " --clock simulated --plan");
  EXPECT_EQ(distributed.exit_code, 0) << distributed.err;
  EXPECT_EQ(enact("metrics " + dir.file("nothing.mcap")).exit_code, 1);
}

TEST(ExperimentCli, PlanIsPrintedWithoutRunning) {
  TempDir dir;
  const RunResult r = enact("experiment " + virtual_tiny(dir, "CM0, CM1, CM2, CM3", 3.0) + " --subjects 2 --plan --out " + dir.file("out"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2 subjects, 4 conditions, balanced order"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("s2_CM2_measured.mcap"), std::string::npos) << r.out;
  std::ifstream none(dir.file("out/plan.csv"));
  EXPECT_FALSE(none.good()) << "nothing written";
}

}  // namespace
}  // namespace enact::test
