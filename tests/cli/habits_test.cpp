// ROS 2 habits on the enact command line: topic info / bw, node list / info, a leading '/'
// in topic names, "did you mean" for misspelled options, topics, nodes and presets, fix
// lines for missing recordings, export to standard output and in relative time, record
// --regex / --exclude, echo --field / --csv, pub.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <sstream>
#include <vector>

#include "tests/cli/cli_support.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

// the highest SCHED_FIFO priority among the threads of process `pid` (0: none runs FIFO),
// from /proc/PID/task/TID/stat (fields 40 rt_priority, 41 policy)
int highest_fifo_priority(pid_t pid) {
  int highest = 0;
  for (const auto& task : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task")) {
    const std::string stat = read_file_or_empty(task.path().string() + "/stat");
    std::istringstream fields(stat.substr(stat.rfind(')') + 2));  // from field 3
    std::vector<std::string> f{"", "", ""};
    for (std::string v; fields >> v;) f.push_back(v);
    if (f.size() > 41 && f[41] == "1") highest = std::max(highest, std::stoi(f[40]));  // 1: SCHED_FIFO
  }
  return highest;
}

TEST(RosHabits, TopicsAndNodesOfARunningGraph) {
  TempDir dir;
  Launcher graph(dir, source_path("launch/bridge_rt.yaml"), 60.0);
  ASSERT_TRUE(graph.wait_log("enact launch: graph ready", 30.0)) << graph.log();
  const std::string at = " --attach " + graph.endpoint();

  // topic info with a ROS-style leading '/': type, publisher, a loop-rate rate
  const RunResult info = enact("topic info /ffd/state" + at);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("type: enact.msgs.DeviceState"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("publishers: rt"), std::string::npos) << info.out;
  const auto rate_at = info.out.find("rate: ");
  ASSERT_NE(rate_at, std::string::npos);
  EXPECT_GT(std::atoi(info.out.c_str() + rate_at + 6), 1000) << info.out;

  // topic bw: a line a second with bytes and messages
  const RunResult bw = enact("topic bw ffd/force --duration 1" + at);
  ASSERT_EQ(bw.exit_code, 0) << bw.err;
  EXPECT_NE(bw.out.find("kB/s"), std::string::npos) << bw.out;
  EXPECT_NE(bw.out.find("messages/s"), std::string::npos) << bw.out;

  // a misspelled topic and node: refused with the closest name
  const RunResult topic = enact("topic echo ffd/stat --count 1" + at);
  EXPECT_EQ(topic.exit_code, 2);
  EXPECT_NE(topic.err.find("did you mean ffd/state?"), std::string::npos) << topic.err;
  const RunResult missing_node = enact("node info r" + at);
  EXPECT_EQ(missing_node.exit_code, 2);
  EXPECT_NE(missing_node.err.find("did you mean rt?"), std::string::npos) << missing_node.err;

  // node list and info: the container, active at the loop rate, its parameters and counters
  const RunResult list = enact("node list" + at);
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_NE(list.out.find("rt             ACTIVE"), std::string::npos) << list.out;
  const RunResult node = enact("node info rt" + at);
  ASSERT_EQ(node.exit_code, 0) << node.err;
  EXPECT_NE(node.out.find("sim.model = CM1"), std::string::npos) << node.out;
  EXPECT_NE(node.out.find("status: ACTIVE"), std::string::npos) << node.out;
  EXPECT_NE(node.out.find("ffd/state      sent"), std::string::npos) << node.out;
  // a component of the co-located graph: its parameters, its node's topics and status
  const RunResult component = enact("node info sim" + at);
  ASSERT_EQ(component.exit_code, 0) << component.err;
  EXPECT_NE(component.out.find("component sim of node rt"), std::string::npos) << component.out;
  EXPECT_NE(component.out.find("\n    model = CM1\n"), std::string::npos) << component.out;
  EXPECT_EQ(component.out.find("rate_hz"), std::string::npos) << "the container's own parameters are rt's\n" << component.out;
  EXPECT_NE(component.out.find("status: ACTIVE"), std::string::npos) << component.out;

  // the loop's FIFO priority in force is what its thread runs at (the graph's profile sets
  // it, not the parameter; 0 where FIFO is refused)
  const RunResult fifo = enact("param get rt.fifo_priority" + at);
  ASSERT_EQ(fifo.exit_code, 0) << fifo.err;
  EXPECT_EQ(std::atoi(fifo.out.c_str()), highest_fifo_priority(graph.pid_of("rt"))) << fifo.out;

  // a short recording, exported to standard output
  const std::string file = dir.file("run.mcap");
  ASSERT_EQ(enact("record -o " + file + " --duration 1" + at).exit_code, 0);
  const RunResult csv = enact("export " + file + " --topic sim/scene --csv -");
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_TRUE(csv.out.starts_with("log_time_ns,")) << csv.out.substr(0, 200);
  EXPECT_GT(std::count(csv.out.begin(), csv.out.end(), '\n'), 10);
  EXPECT_NE(csv.err.find("rows x"), std::string::npos) << csv.err;
  // seconds from the first row
  const RunResult relative = enact("export " + file + " --topic sim/scene --csv - --relative-time");
  ASSERT_EQ(relative.exit_code, 0) << relative.err;
  EXPECT_NE(relative.out.find("\n0.000000000,"), std::string::npos) << relative.out.substr(0, 300);
  EXPECT_TRUE(relative.out.starts_with("time_s,"));
  // a leading '/' is the same topic; a misspelled one gets the closest
  const RunResult slash = enact("export " + file + " --topic /sim/scene --csv -");
  ASSERT_EQ(slash.exit_code, 0) << slash.err;
  EXPECT_EQ(slash.out, csv.out);
  const RunResult typo = enact("export " + file + " --topic sim/scen --csv -");
  EXPECT_EQ(typo.exit_code, 1);
  EXPECT_NE(typo.err.find("did you mean sim/scene?"), std::string::npos) << typo.err;

  // record --regex keeps the topics it matches, --exclude drops those it matches
  const std::string some = dir.file("some.mcap");
  ASSERT_EQ(enact("record -o " + some + " --duration 1 --regex ^ffd/ --exclude force" + at).exit_code, 0);
  const std::string slashed = dir.file("slashed.mcap");
  ASSERT_EQ(enact("record -o " + slashed + " --duration 1 --topics /ffd/state" + at).exit_code, 0);
  EXPECT_NE(enact("info " + slashed).out.find("ffd/state"), std::string::npos);
  const RunResult kept = enact("info " + some);
  EXPECT_NE(kept.out.find("ffd/state"), std::string::npos) << kept.out;
  EXPECT_EQ(kept.out.find("ffd/force"), std::string::npos) << kept.out;
  EXPECT_EQ(kept.out.find("sim/scene"), std::string::npos) << kept.out;
  EXPECT_EQ(enact("record -o " + some + " --duration 1 --regex '(' " + at).exit_code, 1);
}

TEST(RosHabits, EchoFieldsAndPubOnARunningGraph) {
  TempDir dir;
  Launcher graph(dir, source_path("launch/bridge_rt.yaml"), 60.0);
  ASSERT_TRUE(graph.wait_log("enact launch: graph ready", 30.0)) << graph.log();
  const std::string at = " --attach " + graph.endpoint();

  // two fields, tab-separated, one line per message; seqs increase
  const RunResult fields = enact("topic echo ffd/state --count 3 --field header.seq --field position.z" + at);
  ASSERT_EQ(fields.exit_code, 0) << fields.err;
  const std::regex row("([0-9]+)\t(-?[0-9.e-]+)\n");
  std::vector<long> seqs;
  for (auto it = std::sregex_iterator(fields.out.begin(), fields.out.end(), row); it != std::sregex_iterator(); ++it) seqs.push_back(std::stol((*it)[1]));
  ASSERT_EQ(seqs.size(), 3u) << fields.out;
  EXPECT_LT(seqs[0], seqs[1]);
  EXPECT_LT(seqs[1], seqs[2]);
  // a repeated field as a list, one element by index, CSV with a header (the list quoted)
  const RunResult csv = enact("topic echo tactile/frame --count 2 --csv --field rows --field level --field level[15]" + at);
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_TRUE(std::regex_search(csv.out, std::regex("^rows,level,level\\[15\\]\n4,\"\\[[0-9.]+(, [0-9.]+){15}\\]\",[0-9.]+\n"))) << csv.out;
  EXPECT_EQ(std::count(csv.out.begin(), csv.out.end(), '\n'), 3) << csv.out;
  // a message field: one column per field of it
  const RunResult position = enact("topic echo ffd/state --count 2 --csv --field position --field header.seq" + at);
  ASSERT_EQ(position.exit_code, 0) << position.err;
  EXPECT_TRUE(std::regex_search(position.out, std::regex("^position.x,position.y,position.z,header.seq\n(-?[0-9.e-]+,-?[0-9.e-]+,-?[0-9.e-]+,[0-9]+\n){2}$")))
      << position.out;
  // a misspelled field: the message's fields and the closest one
  const RunResult wrong = enact("topic echo ffd/state --once --field positon.z" + at);
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("unknown field 'positon' in enact.msgs.DeviceState (did you mean position?); its fields: header, position, velocity"), std::string::npos)
      << wrong.err;

  // pub: YAML onto a ParamUpdate, applied by the simulator, visible in task/state
  const RunResult model = enact("topic pub /param/set '{name: sim.model, text: CM3}'" + at);
  ASSERT_EQ(model.exit_code, 0) << model.out << model.err;
  EXPECT_NE(model.out.find("publishing #1: name: \"sim.model\" text: \"CM3\""), std::string::npos) << model.out;
  EXPECT_TRUE(std::regex_search(model.out, std::regex("sim.model: applied from ffd/state seq [1-9][0-9]*\n"))) << model.out;
  const RunResult state = enact("topic echo task/state --once --field model" + at);
  EXPECT_EQ(state.out, "CM3\n") << state.err;
  // at a rate, a count of them; a value the simulator refuses: exit 1
  const RunResult repeated = enact("topic pub param/set '{name: sim.stiffness_n_per_m, number: 3000}' --rate 20 --count 3" + at);
  EXPECT_EQ(repeated.exit_code, 0) << repeated.out << repeated.err;
  EXPECT_NE(repeated.out.find("publishing #3"), std::string::npos) << repeated.out;
  EXPECT_EQ(std::count(repeated.out.begin(), repeated.out.end(), '\n'), 6) << repeated.out;
  const RunResult refused = enact("topic pub param/set '{name: sim.stiffness_n_per_m, number: -5}'" + at);
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.out.find("refused: "), std::string::npos) << refused.out;
  // only inbound topics; YAML fields checked by name
  const RunResult outbound = enact("topic pub ffd/force '{}'" + at);
  EXPECT_EQ(outbound.exit_code, 2);
  EXPECT_NE(outbound.err.find("'ffd/force' is not an inbound topic"), std::string::npos) << outbound.err;
  const RunResult misnamed = enact("topic pub param/set '{nam: sim.model, text: CM1}'" + at);
  EXPECT_EQ(misnamed.exit_code, 2);
  EXPECT_NE(misnamed.err.find("unknown field 'nam' in enact.msgs.ParamUpdate (did you mean name?)"), std::string::npos) << misnamed.err;
}

TEST(RosHabits, MisspellingsGetTheClosestName) {
  const RunResult flag = enact("topic hz ffd/state --duratoin 1");
  EXPECT_EQ(flag.exit_code, 2);
  EXPECT_NE(flag.err.find("unknown option --duratoin (did you mean --duration?)"), std::string::npos) << flag.err;
  // commands and their verbs too
  const RunResult command = enact("topc list");
  EXPECT_EQ(command.exit_code, 2);
  EXPECT_NE(command.err.find("unknown command 'topc' (did you mean topic?)"), std::string::npos) << command.err;
  const RunResult verb = enact("node lst");
  EXPECT_EQ(verb.exit_code, 2);
  EXPECT_NE(verb.err.find("unknown verb 'lst' (did you mean list?)"), std::string::npos) << verb.err;
  // an unknown preset is named as one, and no empty table is printed after the error
  const RunResult sim = enact("simulate " + bridge_scene() + " --model CM5");
  EXPECT_EQ(sim.exit_code, 1);
  EXPECT_NE(sim.err.find("unknown preset CM5 (did you mean CM0, CM1, CM2 or CM3?)"), std::string::npos) << sim.err;
  EXPECT_EQ(sim.out, "");
  const RunResult conditions = enact("experiment " + source_path("launch/experiments/bridge_quick.yaml") + " --conditions CM1,CM5 --plan");
  EXPECT_EQ(conditions.exit_code, 1);
  EXPECT_NE(conditions.err.find("unknown preset CM5"), std::string::npos) << conditions.err;
}

TEST(RosHabits, AMissingRecordingGetsTheFixLine) {
  for (const std::string command : {"info", "resim", "play"}) {
    const RunResult r = enact(command + " /nonexistent/run.mcap");
    EXPECT_EQ(r.exit_code, 1) << command;
    EXPECT_NE(r.err.find("No such file"), std::string::npos) << command << ": " << r.err;
    EXPECT_NE(r.err.find("fix:"), std::string::npos) << command << ": " << r.err;
  }
}

}  // namespace
}  // namespace enact::test
