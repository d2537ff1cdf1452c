// enact param list / get / dump / load against the shipped graphs, end to end: every node
// answers for its own parameters through the attach point, a live change shows in list and
// get, dump -> load restores what changed, and a non-live value is refused with the reason.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

struct Shipped {
  const char* file;
  const char* started;                     // the log line once its last node runs
  std::vector<std::string> nodes;          // a parameter of each node (or component)
};

RunResult param(const Launcher& graph, const std::string& args) { return run(kCli + " param " + args + " --attach " + graph.endpoint()); }

class ParamCli : public ::testing::TestWithParam<Shipped> {};

TEST_P(ParamCli, ListGetDumpLoadOnTheShippedGraph) {
  const Shipped& g = GetParam();
  TempDir dir;
  Launcher graph(dir, source_path(g.file), 30.0);
  ASSERT_TRUE(graph.wait_log(g.started, 15.0)) << graph.log();

  // list: every node answers for its own parameters, with value, unit, range and live flag
  const RunResult list = param(graph, "list");
  ASSERT_EQ(list.exit_code, 0) << list.err;
  for (const std::string& p : g.nodes) EXPECT_NE(list.out.find("\n" + p + " "), std::string::npos) << p << "\n" << list.out;
  EXPECT_TRUE(std::regex_search(list.out, std::regex("\nsim\\.model +CM1 +yes\n"))) << list.out;
  EXPECT_TRUE(std::regex_search(list.out, std::regex("\nsim\\.stiffness_n_per_m +6000 +N/m +>= 0 +yes\n"))) << list.out;
  EXPECT_TRUE(std::regex_search(list.out, std::regex("\\.rate_hz +5000 +Hz +1\\.\\.44000 +no\n"))) << list.out;

  // dump of everything, then live changes: list and get show them
  const RunResult dump = param(graph, "dump");
  ASSERT_EQ(dump.exit_code, 0) << dump.err;
  write_file(dir.file("all.yaml"), dump.out);
  ASSERT_EQ(param(graph, "set sim.model CM3").exit_code, 0);
  ASSERT_EQ(param(graph, "set sim.stiffness_n_per_m 3000").exit_code, 0);
  EXPECT_EQ(param(graph, "get sim.model").out, "CM3\n");
  EXPECT_EQ(param(graph, "get sim.stiffness_n_per_m").out, "3000\n");
  EXPECT_TRUE(std::regex_search(param(graph, "list sim").out, std::regex("\nsim\\.model +CM3 +yes\n")));
  const RunResult typo = param(graph, "get sim.modle");
  EXPECT_EQ(typo.exit_code, 1);
  EXPECT_NE(typo.err.find("no parameter 'sim.modle' in the graph (did you mean sim.model?)"), std::string::npos) << typo.err;

  // load the dump: the two live values come back, every other line is unchanged
  const RunResult load = param(graph, "load " + dir.file("all.yaml"));
  EXPECT_EQ(load.exit_code, 0) << load.out << load.err;
  EXPECT_NE(load.out.find(": sim.model = CM1: applied from ffd/state seq "), std::string::npos) << load.out;
  EXPECT_NE(load.out.find(": sim.stiffness_n_per_m = 6000: applied from ffd/state seq "), std::string::npos) << load.out;
  EXPECT_EQ(load.out.find("refused"), std::string::npos) << load.out;
  EXPECT_EQ(param(graph, "get sim.model").out, "CM1\n");
  EXPECT_EQ(param(graph, "get sim.stiffness_n_per_m").out, "6000\n");

  // a node's dump is its param_file (names without the node); a non-live change is refused
  const RunResult sim_dump = param(graph, "dump sim");
  EXPECT_NE(sim_dump.out.find("\nmodel: \"CM1\"\n"), std::string::npos) << sim_dump.out;
  EXPECT_NE(sim_dump.out.find("\nstiffness_n_per_m: \"6000\"\n"), std::string::npos) << "a live number is a param_file's too\n" << sim_dump.out;
  write_file(dir.file("sim_dump.yaml"), sim_dump.out);
  write_file(dir.file("from_dump.yaml"), "launch:\n  - node: {name: sim, exec: enact-sim, param_file: " + dir.file("sim_dump.yaml") + "}\n");
  const RunResult from_dump = run(kCli + " launch " + dir.file("from_dump.yaml") + " --check");
  EXPECT_EQ(from_dump.exit_code, 0) << "a node's dump is a param_file it takes\n" << from_dump.err;
  write_file(dir.file("sim.yaml"), "model: CM2\nmin_fall_s: 2\nmodle: CM1\n");
  const RunResult partial = param(graph, "load " + dir.file("sim.yaml") + " --node sim");
  EXPECT_EQ(partial.exit_code, 1) << partial.out;
  EXPECT_NE(partial.out.find("sim.yaml:1: sim.model = CM2: applied from ffd/state seq "), std::string::npos) << partial.out;
  EXPECT_NE(partial.out.find("sim.yaml:2: min_fall_s = 2: refused: it cannot change while the graph runs (now \"1\")"), std::string::npos) << partial.out;
  EXPECT_NE(partial.out.find("sim.yaml:3: modle = CM1: refused: no such parameter (did you mean model?)"), std::string::npos) << partial.out;
  EXPECT_EQ(param(graph, "get sim.model").out, "CM2\n");

  // set refuses a parameter its node declares fixed, from the node's table
  const std::string fixed = g.nodes.back();
  const RunResult set_fixed = param(graph, "set " + fixed + " 1");
  EXPECT_EQ(set_fixed.exit_code, 1) << set_fixed.out << set_fixed.err;
  EXPECT_NE(set_fixed.out.find(fixed + " = 1: refused: it cannot change while the graph runs"), std::string::npos) << set_fixed.out;
}

INSTANTIATE_TEST_SUITE_P(Shipped, ParamCli,
                         ::testing::Values(Shipped{"launch/bridge_rt.yaml", "started rt", {"rt.rate_hz", "sim.scene", "ffd.hand_path", "tactile.rise_time_s"}},
                                           Shipped{"launch/bridge.yaml", "started ffd", {"sim.scene", "ffd.rate_hz", "ffd.hand_path", "tactile.rise_time_s", "tactile.shown_rate_hz"}}),
                         [](const auto& info) { return info.index == 0 ? std::string("CoLocated") : std::string("Distributed"); });

// a node's --help lists its declared parameters, and the node refuses a typo with did-you-mean
// and a bad value naming the fix before it starts
TEST(NodeParams, HelpAndRefusalComeFromTheTable) {
  const std::string sim = ENACT_SIM;
  const RunResult help = run(sim + " --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("  change_ramp_s=0.05"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("  stiffness_n_per_m"), std::string::npos) << help.out;
  const RunResult typo = run(sim + " --check --param scene=" + source_path("launch/scenes/bridge.yaml") + " --param scene_rate=30");
  EXPECT_EQ(typo.exit_code, 1);
  EXPECT_NE(typo.err.find("parameter 'scene_rate' is not a parameter of sim (did you mean scene_rate_hz?)"), std::string::npos) << typo.err;
  const RunResult bad = run(sim + " --check --param scene=" + source_path("launch/scenes/bridge.yaml") + " --param change_ramp_s=-1");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("parameter 'change_ramp_s' is out of range, got '-1' (allowed: 0..10)\n  fix: write e.g. change_ramp_s=0.05 (s)"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace enact::test
