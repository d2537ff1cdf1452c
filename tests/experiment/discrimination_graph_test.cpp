// Discrimination trials on the graph, through `enact experiment`: virtual observers in
// simulated time (each trial's recording holds its two intervals, set on param/set and
// acknowledged by the simulator at the plan's values; the answers are the seeded observers';
// a rerun writes the same trials.csv), the switches never jolt the hand, and a person
// answers at the keyboard (a script typing on the command's stdin) in real time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/devices/device_profile.h"
#include "core/experiment/discrimination.h"
#include "core/record/reader.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/task_event.pb.h"
#include "tests/cli/cli_support.h"
#include "tests/experiment/experiment_run.h"
#include "tests/support/test_util.h"

namespace enact::test {
namespace {

constexpr double kInterval_s = 0.5;
constexpr double kRate_hz = 5000.0;  // trial_rt.yaml's

// a discrimination file on the co-located trial graph, the hand pressing the bridge's top
std::string discrimination_file(const TempDir& dir, const std::string& who, const std::string& levels, const std::string& conditions = "CM1") {
  const std::string path = dir.file("disc.yaml");
  write_file(path, "name: disc\nkind: discrimination\nseed: 5\n" + who + "conditions: [" + conditions + "]\nparameter: stiffness_n_per_m\nreference: 600\n" +
                       "graph: " + source_path("launch/experiments/trial_rt.yaml") + "\nlaunch_args: {hand_path: " +
                       source_path("launch/experiments/press.csv") + "}\ninterval_s: " + std::to_string(kInterval_s) +
                       "\nprocedures:\n  - {kind: constant, levels: [" + levels + "], repetitions: 1}\nanalysis: {shape: gaussian, bootstrap: 0}\n");
  return path;
}

// what a trial's recording holds: the runner's task events, the simulator's applied
// stiffness changes, and the force of each tick
struct Recorded {
  std::vector<msgs::TaskEvent> events;  // the runner's
  std::vector<msgs::ParamAck> acks;     // applied, one per request
  std::map<std::uint64_t, double> force_n;  // by the device state seq it answers
  std::map<std::uint64_t, std::int64_t> stamp_ns;  // each device state's, by seq
};

Recorded read_recording(const std::string& path) {
  Recorded r;
  record::Reader reader(path);
  reader.for_each([&](const record::Message& m) {
    const auto parse = [&](auto& msg) { return msg.ParseFromArray(m.data.data(), static_cast<int>(m.data.size())); };
    if (m.topic == "task/event") {
      msgs::TaskEvent e;
      if (parse(e) && e.header().source() == "experiment") r.events.push_back(e);
    } else if (m.topic == "param/ack") {
      // one per request (a request sent again is answered again)
      msgs::ParamAck a;
      const auto same = [&](const msgs::ParamAck& b) { return b.request_id() == a.request_id(); };
      if (parse(a) && a.applied() && std::none_of(r.acks.begin(), r.acks.end(), same)) r.acks.push_back(a);
    } else if (m.topic == "ffd/state") {
      msgs::DeviceState d;
      if (parse(d)) r.stamp_ns[d.header().seq()] = d.header().stamp_ns();
    } else if (m.topic == "ffd/force") {
      msgs::ForceCommand f;
      if (parse(f)) r.force_n[f.answered_seq()] = std::sqrt(f.force().x() * f.force().x() + f.force().y() * f.force().y() + f.force().z() * f.force().z());
    }
    return true;
  });
  return r;
}

// trials.csv's row as the plan put it: the value of interval 1 and 2
std::vector<double> interval_values(const std::vector<std::string>& row) {
  const double reference = std::stod(row[6]), comparison = std::stod(row[7]);
  return row[9] == "1" ? std::vector<double>{reference, comparison} : std::vector<double>{comparison, reference};
}

// the recording holds the trial's two intervals at the values of its row: the simulator
// acknowledged each (the step it took effect), the runner announced each there
void expect_intervals(const Recorded& r, const std::vector<std::string>& row) {
  using E = msgs::TaskEvent;
  std::vector<E::Kind> kinds;
  for (const auto& e : r.events) kinds.push_back(e.kind());
  EXPECT_EQ(kinds, (std::vector<E::Kind>{E::CONDITION, E::TRIAL_START, E::INTERVAL_START, E::INTERVAL_END, E::INTERVAL_START, E::INTERVAL_END, E::ANSWER}));
  const std::vector<double> values = interval_values(row);
  ASSERT_EQ(r.acks.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(r.acks[i].name(), "sim.stiffness_n_per_m");
    EXPECT_NEAR(r.acks[i].number(), values[i], 1e-9) << "interval " << i + 1;
  }
  if (kinds.size() != 7u) return;
  // each interval begins at the step its value took effect, and lasts interval_s at least
  const std::string seq1 = "seq " + std::to_string(r.acks[0].state_seq()), seq2 = "seq " + std::to_string(r.acks[1].state_seq());
  EXPECT_NE(r.events[2].detail().find(seq1), std::string::npos) << r.events[2].detail();
  EXPECT_NE(r.events[3].detail().find(seq2), std::string::npos) << r.events[3].detail();
  EXPECT_NE(r.events[4].detail().find(seq2), std::string::npos) << r.events[4].detail();
  // on the graph's clock (a real-time loop that missed deadlines skips ticks)
  ASSERT_TRUE(r.stamp_ns.count(r.acks[0].state_seq()) && r.stamp_ns.count(r.acks[1].state_seq()));
  EXPECT_GE(r.stamp_ns.at(r.acks[1].state_seq()) - r.stamp_ns.at(r.acks[0].state_seq()), static_cast<std::int64_t>(kInterval_s * 1e9));
  EXPECT_NE(r.events[6].detail().find("interval " + row[10]), std::string::npos) << r.events[6].detail();
}

// two virtual observers, two levels each, in simulated time, run twice
class DiscriminationOnTheGraph : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    file_ = discrimination_file(*dir_, "subjects: 2\nvirtual_observers: {weber_fraction: 0.15, lapse: 0.0}\n", "60, 240");
    for (const char* out : {"out", "again"}) {
      const RunResult r = enact("experiment " + file_ + " --clock simulated --out " + dir_->file(out));
      exit_codes_.push_back(r.exit_code);
      terminal_ += r.err;
    }
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string recording(const std::vector<std::string>& row) { return dir_->file("out/trials/s" + row[0] + "_" + row[1] + "_t00" + row[4] + ".mcap"); }

  static TempDir* dir_;
  static std::string file_, terminal_;
  static std::vector<int> exit_codes_;
};
TempDir* DiscriminationOnTheGraph::dir_ = nullptr;
std::string DiscriminationOnTheGraph::file_, DiscriminationOnTheGraph::terminal_;
std::vector<int> DiscriminationOnTheGraph::exit_codes_;

TEST_F(DiscriminationOnTheGraph, EachTrialRecordsItsTwoIntervalsAtThePlansValues) {
  ASSERT_EQ(exit_codes_, (std::vector<int>{0, 0})) << terminal_;
  const auto rows = csv_rows(dir_->file("out/trials.csv"));
  ASSERT_EQ(rows.size(), 5u) << "2 subjects x 2 levels";
  EXPECT_EQ(rows[0].back(), "response_time_s");
  for (std::size_t i = 1; i < rows.size(); ++i) {
    SCOPED_TRACE(rows[i][0] + " trial " + rows[i][4]);
    expect_intervals(read_recording(recording(rows[i])), rows[i]);
  }
}

TEST_F(DiscriminationOnTheGraph, TheAnswersAreTheSeededObserversAndARerunIsIdentical) {
  ASSERT_EQ(exit_codes_, (std::vector<int>{0, 0})) << terminal_;
  const experiment::DiscriminationSpec spec = experiment::load_discrimination(file_);
  const std::vector<experiment::DiscriminationBlock> blocks = experiment::make_blocks(spec);
  const auto rows = csv_rows(dir_->file("out/trials.csv"));
  ASSERT_EQ(rows.size(), 5u);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto& row = rows[i];
    const auto block = std::find_if(blocks.begin(), blocks.end(), [&](const auto& b) { return b.subject == row[0] && b.condition.label == row[1]; });
    ASSERT_NE(block, blocks.end());
    const int larger = row[9] == "1" ? 2 : 1;
    EXPECT_EQ(std::stoi(row[10]), block->observer.chosen_interval(std::stoul(row[4]) - 1, std::stod(row[8]), larger)) << row[0] << " trial " << row[4];
    EXPECT_EQ(row[11], std::stoi(row[10]) == larger ? "1" : "0");
    EXPECT_EQ(row[12], "0") << "an observer answers as the last interval ends";
  }
  EXPECT_EQ(read_file(dir_->file("again/trials.csv")), read_file(dir_->file("out/trials.csv")));
  EXPECT_EQ(read_file(dir_->file("again/summary.csv")), read_file(dir_->file("out/summary.csv")));
}

TEST_F(DiscriminationOnTheGraph, AnIntervalSwitchNeverJoltsTheHand) {
  ASSERT_EQ(exit_codes_, (std::vector<int>{0, 0})) << terminal_;
  // the device's limit on a force step, per tick
  const double limit_n = devices::find_device_profile("ergos")->max_force_step_n_per_ms * 1e3 / kRate_hz;
  const auto rows = csv_rows(dir_->file("out/trials.csv"));
  ASSERT_EQ(rows.size(), 5u);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const Recorded r = read_recording(recording(rows[i]));
    ASSERT_EQ(r.acks.size(), 2u);
    // the switch from interval 1 to 2 comes interval_s after the first: the hand presses then
    ASSERT_TRUE(r.force_n.count(r.acks[1].state_seq() - 1)) << "the tick before the switch is recorded";
    EXPECT_GT(r.force_n.at(r.acks[1].state_seq() - 1), 0.5) << "the hand presses the top as the value switches";
    // anywhere in the trial (where each interval begins depends on when the runner's request
    // came: the hand's own contact may fall in a switch's ramp), and at each switch: the scene's
    // stiffness to interval 1's, then interval 1's to 2's
    double anywhere_n = 0.0;
    for (const auto& [seq, force_n] : r.force_n) {
      if (r.force_n.count(seq - 1)) anywhere_n = std::max(anywhere_n, std::abs(force_n - r.force_n.at(seq - 1)));
    }
    EXPECT_LE(anywhere_n, limit_n) << rows[i][0] << " trial " << rows[i][4];
    for (const msgs::ParamAck& ack : r.acks) {
      const std::uint64_t at = ack.state_seq();
      // interval 1's value may come before the first tick (the runner sends it once the graph
      // is up: CI28): the force before it is the device's zero at the start
      ASSERT_TRUE(at == 1 || r.force_n.count(at - 1)) << "the tick before the switch is recorded";
      const auto before_n = [&](std::uint64_t seq) { return seq == 1 ? 0.0 : r.force_n.at(seq - 1); };
      // over the change's ramp (50 ms) and after
      double largest_n = 0.0;
      for (std::uint64_t seq = at; seq < at + 500 && r.force_n.count(seq); ++seq) largest_n = std::max(largest_n, std::abs(r.force_n.at(seq) - before_n(seq)));
      EXPECT_LE(largest_n, limit_n) << rows[i][0] << " trial " << rows[i][4] << ", switch at seq " << at;
    }
  }
}

TEST(DiscriminationPeople, APersonAnswersAtTheKeyboardAfterBothIntervals) {
  TempDir dir;
  const std::string file = discrimination_file(dir, "subjects: [P1]\n", "150, 300");
  Experiment run(dir, {file, "--out", dir.file("out")});
  ASSERT_TRUE(run.wait_for("next: subject P1, condition CM1", 1, 60.0)) << run.terminal();
  run.type("\n");
  const std::vector<std::string> typed{"2", "1"};
  for (std::size_t i = 0; i < typed.size(); ++i) {
    ASSERT_TRUE(run.wait_for("which interval had the larger stiffness_n_per_m", static_cast<int>(i + 1), 60.0)) << run.terminal();
    run.type(typed[i] + "\n");
  }
  ASSERT_EQ(run.wait_exit(60.0), 0) << run.terminal();
  const auto rows = csv_rows(dir.file("out/trials.csv"));
  ASSERT_EQ(rows.size(), 3u) << run.terminal();
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto& row = rows[i];
    SCOPED_TRACE("trial " + row[4]);
    EXPECT_EQ(row[10], typed[i - 1]) << "the interval typed";
    EXPECT_EQ(row[11], row[10] != row[9] ? "1" : "0") << "correct when the comparison's interval was named";
    EXPECT_GT(std::stod(row[12]), 0.0) << "a person takes time to answer";
    expect_intervals(read_recording(dir.file("out/trials/sP1_CM1_t00" + row[4] + ".mcap")), row);
  }
  // the person is told which interval runs, never its value
  EXPECT_NE(run.terminal().find("interval 2"), std::string::npos) << run.terminal();
  EXPECT_EQ(run.terminal().find("(reference)"), std::string::npos) << run.terminal();
}

TEST(DiscriminationPeople, AStudyStoppedAtAPromptResumesWhereItStopped) {
  TempDir dir;
  const std::string file = discrimination_file(dir, "subjects: [P1]\norder: balanced\n", "150", "CM0, CM1");
  {
    Experiment run(dir, {file, "--out", dir.file("out")});
    ASSERT_TRUE(run.wait_for("next: subject P1, condition CM0", 1, 60.0)) << run.terminal();
    run.type("\n");
    ASSERT_TRUE(run.wait_for("which interval had the larger", 1, 60.0)) << run.terminal();
    run.type("1\n");
    // the experimenter stops before the next condition
    ASSERT_TRUE(run.wait_for("next: subject P1, condition CM1", 1, 60.0)) << run.terminal();
    run.type("q\n");
    EXPECT_EQ(run.wait_exit(60.0), 130) << run.terminal();
  }
  ASSERT_EQ(csv_rows(dir.file("out/trials.csv")).size(), 2u);
  // run again (its terminal in a folder of its own): CM0 is done, CM1 is asked for
  TempDir terminal;
  Experiment again(terminal, {file, "--out", dir.file("out")});
  ASSERT_TRUE(again.wait_for("next: subject P1, condition CM1", 1, 60.0)) << again.terminal();
  EXPECT_EQ(again.terminal().find("condition CM0 ("), std::string::npos) << "CM0 is not asked again: " << again.terminal();
  again.type("\n");
  ASSERT_TRUE(again.wait_for("which interval had the larger", 1, 60.0)) << again.terminal();
  again.type("2\n");
  ASSERT_EQ(again.wait_exit(60.0), 0) << again.terminal();
  const auto rows = csv_rows(dir.file("out/trials.csv"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1][1], "CM0");
  EXPECT_EQ(rows[1][10], "1");
  EXPECT_EQ(rows[2][1], "CM1");
  EXPECT_EQ(rows[2][10], "2");
  EXPECT_EQ(csv_rows(dir.file("out/summary.csv")).size(), 3u) << "both conditions summarised";
}

}  // namespace
}  // namespace enact::test
