// The recordings' and `enact topic`'s loss count per publisher: jumps, and restarts whose
// first messages were missed; what a launch file tells the graph's observers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "core/record/logger.h"
#include "core/session/launch_info.h"
#include "core/graph/graph_dir.h"
#include "tests/support/test_util.h"

namespace enact::graph {
namespace {

TEST(SequenceCheck, CountsJumpsAndTheMissedStartOfARestartedStream) {
  SequenceCheck c;
  for (const std::uint64_t seq : {1, 2, 5, 6, 3, 4, 1, 2}) c.add(seq);
  // 3-4 missing; a restart seen at 3 (its 1-2 missing); a restart seen at 1 (nothing missing)
  EXPECT_EQ(c.messages, 8u);
  EXPECT_EQ(c.gaps, 4u);
  EXPECT_EQ(c.restarts, 2u);
}

// a message the attach point sends again (a latched topic's last, for a late observer) is a
// repeat; another with the same seq, from another process of the same source (two `enact
// param set`, each counting from 1), is not
TEST(SequenceCheck, OnlyTheSameMessageAgainIsARepeat) {
  SequenceCheck c;
  c.add(1, 1'000);
  EXPECT_TRUE(c.repeats(1, 1'000));
  EXPECT_FALSE(c.repeats(1, 2'000));
  EXPECT_FALSE(c.repeats(2, 1'000));
}

TEST(SequenceCheck, ALateJoinerLosesNothing) {
  SequenceCheck c;
  for (const std::uint64_t seq : {500, 501, 502}) c.add(seq);
  EXPECT_EQ(c.gaps, 0u);
  EXPECT_EQ(c.restarts, 0u);
}

// the nodes `enact param` waits for while a graph starts: those of enact's node host (each
// publishes param/values/<node>), not a user's own executable
TEST(LaunchInfo, NamesTheNodesThatPublishTheirParameters) {
  launch::LaunchDescription graph;
  for (const auto& [name, exec] : {std::pair{"sim", "enact-sim"}, {"ffd", "/opt/enact/bin/enact-ffd"}, {"mine", "/usr/bin/python3"}, {"log", "enact-logger"}}) {
    launch::NodeSpec n;
    n.name = name;
    n.exec = exec;
    graph.nodes.push_back(n);
  }
  const msgs::GraphInfo info = launch_info("no-such-launch-file.yaml", graph);
  EXPECT_EQ(std::vector<std::string>(info.param_nodes().begin(), info.param_nodes().end()), (std::vector<std::string>{"sim", "ffd", "log"}));
}

// a scene given as the shipped one's path (found in enact's share, not where the user stands,
// as its node finds it) is kept in the graph's info with the files it reads beside it: the
// viewer draws it from there
TEST(LaunchInfo, AShippedSceneNamedFromElsewhereIsKept) {
  ASSERT_FALSE(std::filesystem::exists("launch/scenes/ridge.yaml")) << "the test runs outside the source tree";
  launch::LaunchDescription graph;
  launch::NodeSpec n;
  n.name = "sim";
  n.exec = "enact-sim";
  n.params.push_back({"scene", "launch/scenes/ridge.yaml", ""});
  graph.nodes.push_back(n);
  const msgs::GraphInfo info = launch_info("no-such-launch-file.yaml", graph);
  std::map<std::string, std::string> kept;
  for (const auto& f : info.files()) kept[f.name()] = f.data();
  ASSERT_TRUE(kept.count("sim.scene")) << "the scene kept";
  std::ifstream source(test::source_path("launch/scenes/ridge.yaml"));
  std::stringstream text;
  text << source.rdbuf();
  EXPECT_EQ(kept["sim.scene"], text.str());
  EXPECT_TRUE(kept.count("sim.scene/ridge_heights.png")) << "and its height map";
  EXPECT_EQ(info.params(0).value(), "launch/scenes/ridge.yaml") << "the parameter as given";
}

// a graph still starting: `enact param`, `enact topic` and `enact record --topics` wait for
// the nodes that have not declared their topics
TEST(LaunchInfo, TheNodesNotAnnouncedAreThoseWithoutTheirParameterTopic) {
  msgs::GraphInfo info;
  info.add_param_nodes("sim");
  info.add_param_nodes("ffd");
  info.add_topics()->set_name("sim/frame");
  info.add_topics()->set_name("param/values/sim");
  info.add_topics()->set_name("param/values/ffdx");
  EXPECT_EQ(nodes_not_announced(info), std::vector<std::string>{"ffd"});
  info.add_topics()->set_name("param/values/ffd");
  EXPECT_TRUE(nodes_not_announced(info).empty());
  EXPECT_TRUE(nodes_not_announced(msgs::GraphInfo{}).empty()) << "a graph not started from a launch file names none";
}

}  // namespace
}  // namespace enact::graph
