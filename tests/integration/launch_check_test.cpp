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
                       Bad{rt, "rate_hz=100000", "rate_hz 100000 is out of range"}, Bad{distributed, "model=CM9", "unknown preset CM9"},
                       Bad{source_path("launch/replay_sim.yaml"), "recording=/nonexistent/run.mcap", "cannot open"}}) {
    for (const char* mode : {" --check", " --duration 5"}) {
      const RunResult r = enact("launch " + b.file + " --arg " + b.arg + mode);
      EXPECT_EQ(r.exit_code, 1) << b.arg << mode << "\n" << r.err;
      EXPECT_NE(r.err.find(b.said), std::string::npos) << r.err;
      EXPECT_NE(r.err.find(".yaml:"), std::string::npos) << "the node's launch file line\n" << r.err;
      EXPECT_NE(r.err.find("(the value comes from --arg " + b.arg + ")"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("fix:"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("nothing started"), std::string::npos) << r.err;
      EXPECT_EQ(r.err.find("enact launch: started"), std::string::npos) << "a process started\n" << r.err;
    }
  }
  const RunResult good = enact("launch " + rt + " --check");
  EXPECT_EQ(good.exit_code, 0) << good.err;
  EXPECT_NE(good.out.find("every node accepts its parameters"), std::string::npos) << good.out;
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
