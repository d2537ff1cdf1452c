// `enact launch --check` (and every launch) has each node check its parameters after
// substitution before anything starts; `enact experiment --plan` checks every trial graph.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/test_util.h"

namespace enact::test {
namespace {

RunResult enact(const std::string& args) { return run(std::string(ENACT_CLI) + " " + args); }

struct Bad {
  std::string file, arg, said;
};

TEST(LaunchCheck, BadParameterValuesAreRefusedBeforeAnythingStarts) {
  const std::string rt = source_path("launch/bridge_rt.yaml"), distributed = source_path("launch/bridge.yaml");
  for (const Bad& b : {Bad{rt, "model=CM9", "unknown preset CM9"}, Bad{rt, "rate_hz=fast", "'rate_hz' must be a finite number"},
                       Bad{rt, "rate_hz=100000", "'rate_hz' is out of range, got '100000' (allowed: 1..44000)"}, Bad{distributed, "model=CM9", "unknown preset CM9"},
                       Bad{source_path("launch/replay_sim.yaml"), "recording=/nonexistent/run.mcap", "cannot open"}}) {
    for (const char* mode : {" --check", " --duration 5"}) {
      const RunResult r = enact("launch " + b.file + " --arg " + b.arg + mode);
      EXPECT_EQ(r.exit_code, 1) << b.arg << mode << "\n" << r.err;
      EXPECT_NE(r.err.find(b.said), std::string::npos) << r.err;
      EXPECT_NE(r.err.find(".yaml:"), std::string::npos) << "the node's launch file line\n" << r.err;
      EXPECT_NE(r.err.find("--arg " + b.arg), std::string::npos) << "where the value came from\n" << r.err;
      EXPECT_NE(r.err.find("fix:"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("nothing started"), std::string::npos) << r.err;
      EXPECT_EQ(r.err.find("enact launch: started"), std::string::npos) << "a process started\n" << r.err;
    }
  }
  const RunResult good = enact("launch " + rt + " --check");
  EXPECT_EQ(good.exit_code, 0) << good.err;
  EXPECT_NE(good.out.find("every node accepts its parameters"), std::string::npos) << good.out;
}

// the node tables: a typo and a bad value name the line of the parameter (its file:line, or
// the --arg it came from), before any node runs
TEST(LaunchCheck, UnknownNamesAndBadValuesNameTheirLine) {
  TempDir dir;
  const std::string file = dir.file("g.yaml");
  write_file(file, "launch:\n"
                   "  - arg: {name: rate, default: \"5000\"}\n"
                   "  - container:\n"
                   "      name: rt\n"
                   "      param:\n"
                   "        - {name: rate_hz, value: \"$(var rate)\"}\n"
                   "        - {name: shown_rate_hz, value: \"-1\"}\n"
                   "      component:\n"
                   "        - name: sim\n"
                   "          plugin: sim\n"
                   "          param:\n"
                   "            - {name: scene, value: " + source_path("launch/scenes/bridge.yaml") + "}\n"
                   "            - {name: modle, value: CM2}\n"
                   "        - {name: ffd, plugin: ffd}\n"
                   "        - {name: tactile, plugin: tactile, param: [{name: device, value: metek}]}\n"
                   "        - {name: rec, plugin: logger, param: [{name: compression, value: zip}]}\n");
  const RunResult r = enact("launch " + file + " --check --arg rate=fast");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("--arg rate=fast (" + file + ":6): node 'rt': parameter 'rate_hz' must be a finite number"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ":7: node 'rt': parameter 'shown_rate_hz' is out of range, got '-1' (allowed: > 0)\n  fix: write e.g. shown_rate_hz=100 (Hz)"),
            std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ":13: node 'sim': parameter 'modle' is not a parameter of sim (did you mean model?)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ":15: node 'tactile': parameter 'device' must be one of simulated, metec, got 'metek' (did you mean metec?)"),
            std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file + ":16: node 'rec': parameter 'compression' must be one of zstd, lz4, none, got 'zip'"), std::string::npos)
      << "an observer component's parameters are checked as its node's\n" << r.err;
  EXPECT_NE(r.err.find("nothing started (5 parameter problems)"), std::string::npos) << r.err;
}

// a container's component list that cannot run is refused at the line of the entry (of the
// container when one is missing), naming the plugins there are and the fix
TEST(LaunchCheck, ImpossibleComponentListsNameTheirLine) {
  TempDir dir;
  struct Case {
    std::string components;
    int line;
    std::string said;
  };
  for (const Case& c : {Case{"        - {name: sim, plugin: sim}\n        - {name: ffd, plugin: fdd}\n", 7, "component 'ffd': unknown plugin 'fdd'"},
                        Case{"        - {name: sim, plugin: sim}\n        - {name: tactile, plugin: tactile}\n", 4, "it has no force-feedback device (plugin ffd)"},
                        Case{"        - {name: a, plugin: tactile}\n        - {name: b, plugin: tactile}\n", 7, "components 'a' and 'b' are both a tactile display (plugin tactile)"}}) {
    const std::string file = dir.file("g.yaml");
    write_file(file, "launch:\n"
                     "  - arg: {name: rate, default: \"5000\"}\n"
                     "  - container:\n"
                     "      name: rt\n"
                     "      component:\n" + c.components);
    const RunResult r = enact("launch " + file + " --check");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find(file + ":" + std::to_string(c.line) + ": node 'rt': " + c.said), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("fix:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("sim (simulator), ffd (force-feedback device), tactile (tactile display)"), std::string::npos) << "the plugins there are\n" << r.err;
  }
}

TEST(LaunchCheck, ExperimentPlanChecksEveryTrialGraph) {
  TempDir dir;
  const std::string file = dir.file("exp.yaml");
  write_file(file, "name: bad\nseed: 1\nsubjects: 1\nvirtual_subject: " + source_path("launch/experiments/subjects/quick.yaml") +
                       "\nconditions: [CM1]\nlimit_s: 3\ngraph: " + source_path("launch/experiments/trial_rt.yaml") + "\nlaunch_args: {rate_hz: fast}\n");
  const RunResult r = enact("experiment " + file + " --plan --out " + dir.file("out"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("condition CM1:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'rate_hz' must be a finite number"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace enact::test
