// One component, two hosts: the bridge run by its distributed graph (a process per component)
// and by its co-located container, in simulated time, for the same model seconds. Each
// component ends the same way in either host and says so in the same words.
#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>
#include <string>

#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

// what a run printed (stderr, where the nodes speak as they go, then stdout)
std::string launched(const std::string& file, const std::string& more = "") {
  const RunResult r = run(kCli + " launch " + source_path(file) + " --clock simulated --arg duration_s=1 --arg realtime=false" + more);
  EXPECT_EQ(r.exit_code, 0) << file << "\n" << r.out << r.err;
  return r.err + r.out;
}

// the number in "<node>: N frames applied; ..." of the tactile driver's summary line (-1: none)
long frames_applied(const std::string& log) {
  std::smatch m;
  if (!std::regex_search(log, m, std::regex("(^|\\n)tactile: ([0-9]+) frames applied; [^\\n]*pins lowered\\."))) return -1;
  return std::stol(m[2]);
}

TEST(BothHosts, EachComponentEndsTheSameWayAndSaysSoInTheSameWords) {
  const std::string distributed = launched("launch/bridge.yaml"), colocated = launched("launch/bridge_rt.yaml");
  // the force device: its safety layer's line, the force zeroed before the device went off
  const std::regex force_line("(^|\\n)ffd: [^\\n]*; force steps held to the profile's limit: [0-9]+, re-engagements: [0-9]+; "
                              "force at exit: zeroed before the device was switched off");
  EXPECT_TRUE(std::regex_search(distributed, force_line)) << distributed;
  EXPECT_TRUE(std::regex_search(colocated, force_line)) << colocated;
  // the tactile display: every frame of the model's second applied, the pins lowered; one may
  // still be in flight when the distributed graph stops
  const long frames_distributed = frames_applied(distributed), frames_colocated = frames_applied(colocated);
  EXPECT_GT(frames_colocated, 10) << colocated;
  EXPECT_LE(std::labs(frames_distributed - frames_colocated), 1L) << distributed << "\n---\n" << colocated;
  // the simulator: the task as it ended and the body's re-synchronisations with the device (the
  // start's), in the same words; the same model second, so the same falls and progress
  const std::regex sim_line("(^|\\n)sim: task: falls ([0-9]+), progress ([0-9.]+)[^;\\n]*; re-synchronised with the device ([0-9]+) times? "
                            "\\(largest offset [0-9.]+ mm\\)");
  std::smatch d, c;
  ASSERT_TRUE(std::regex_search(distributed, d, sim_line)) << distributed;
  ASSERT_TRUE(std::regex_search(colocated, c, sim_line)) << colocated;
  EXPECT_EQ(d[2], c[2]) << d[0] << "\n" << c[0];
  EXPECT_NEAR(std::stod(d[3]), std::stod(c[3]), 0.011) << d[0] << "\n" << c[0];
  EXPECT_EQ(d[4], "1") << d[0];
  EXPECT_EQ(c[4], "1") << c[0];
  // the container's loop thread says what it set up (memory locked) as it starts, before the
  // node is ready, on one line (not in its summary, on stdout at the end)
  const std::size_t locked = colocated.find("\nrt: memory locked (mlockall current and future pages)\n");
  ASSERT_NE(locked, std::string::npos) << colocated;
  EXPECT_LT(locked, colocated.find("rt ready")) << colocated;
}

// a scene without a task: no falls, progress or time on the top to count, in either line
TEST(BothHosts, ASceneWithoutATaskPrintsNoTaskMetrics) {
  const std::string log = launched("launch/bridge_rt.yaml", " --arg scene=" + source_path("launch/scenes/two_boxes.yaml"));
  EXPECT_TRUE(std::regex_search(log, std::regex("(^|\\n)sim: re-synchronised with the device 1 time \\(largest offset [0-9.]+ mm\\)(; [0-9]+ late samples? held [^\\n]*)?\\n"))) << log;
  EXPECT_EQ(log.find("falls"), std::string::npos) << log;
  EXPECT_EQ(log.find("progress"), std::string::npos) << log;
  EXPECT_EQ(log.find("on the top"), std::string::npos) << log;
  EXPECT_NE(log.find("rt: the hand felt: mean |F|"), std::string::npos) << log;
}

// in simulated time nobody is there once the task is completed: either host ends its run at
// that tick by itself (the scripted walk completes the bridge in 9.1 model seconds), says so,
// and the graph ends well before the launcher's own limit
TEST(BothHosts, InSimulatedTimeEitherGraphEndsWithItsTask) {
  for (const char* file : {"launch/bridge.yaml", "launch/bridge_rt.yaml"}) {
    const RunResult r = run(kCli + " launch " + source_path(file) + " --clock simulated --arg realtime=false --duration 300");
    const std::string log = r.out + r.err;
    EXPECT_EQ(r.exit_code, 0) << file << "\n" << log;
    EXPECT_NE(log.find("ffd: the task is completed: the run ends here (simulated time)"), std::string::npos) << file << "\n" << log;
    EXPECT_EQ(log.find("duration reached"), std::string::npos) << file << ": it ran on to the launcher's limit\n" << log;
    EXPECT_TRUE(std::regex_search(log, std::regex("progress [0-9.]+ \\(completed\\)"))) << file << "\n" << log;
  }
}

}  // namespace
}  // namespace enact::test
