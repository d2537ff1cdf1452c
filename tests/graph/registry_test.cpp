// The registry of running graphs: what an entry records of its real-time loop, read back by
// the next launcher to place its own loop elsewhere; the rule that picks a graph from it.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <map>
#include <string>
#include <vector>

#include "core/session/registry.h"
#include "tests/support/test_util.h"

namespace enact::test {
namespace {

TEST(Registry, RunningLoopsAreTheCpusTheLiveEntriesHold) {
  TempDir dir;
  ASSERT_EQ(setenv("ENACT_REGISTRY", dir.path().c_str(), 1), 0);
  {
    const graph::Registration rt_graph("bridge_rt", "tcp://127.0.0.1:1", "launch/bridge_rt.yaml", "", false, "1");
    const graph::Registration player("replay", "tcp://127.0.0.1:2", "run.mcap", "");  // no loop
    EXPECT_EQ(graph::running_loops(), (std::map<int, std::string>{{1, "bridge_rt"}}));
    const graph::Registration wide("wide", "tcp://127.0.0.1:3", "x.yaml", "", false, "2,3");
    EXPECT_EQ(graph::running_loops(), (std::map<int, std::string>{{1, "bridge_rt"}, {2, "wide"}, {3, "wide"}}));
  }
  // gone with their graphs
  EXPECT_TRUE(graph::running_loops().empty());
  unsetenv("ENACT_REGISTRY");
}

// the one rule every tool, observer node and the viewer finds its graph by
graph::GraphEntry entry(const std::string& name, const std::string& endpoint) {
  graph::GraphEntry e;
  e.name = name;
  e.endpoint = endpoint;
  return e;
}

// the endpoint picked among `graphs` for --graph, a prefix, --attach and the endpoint in use
// ("none": none fits)
std::string picked(const std::vector<graph::GraphEntry>& graphs, const std::string& name, const std::string& prefix = "", const std::string& endpoint = "",
                   const std::string& current = "") {
  graph::AttachChoice choice;
  choice.graph = name;
  choice.prefix = prefix;
  choice.endpoint = endpoint;
  const auto g = graph::pick_graph(choice, graphs, current);
  return g ? g->name + " " + g->endpoint : "none";
}

TEST(Registry, OneRulePicksTheGraphForToolsObserversAndTheViewer) {
  unsetenv("ENACT_ATTACH");
  const std::vector<graph::GraphEntry> two{entry("bridge", "tcp://127.0.0.1:1"), entry("bridge_rt", "tcp://127.0.0.1:2")};
  // named, by prefix, by endpoint (registered here or not)
  EXPECT_EQ(picked(two, "bridge_rt"), "bridge_rt tcp://127.0.0.1:2");
  EXPECT_EQ(picked(two, "ridge"), "none");
  EXPECT_EQ(picked(two, "", "bridge_"), "bridge_rt tcp://127.0.0.1:2");
  EXPECT_EQ(picked(two, "", "", "tcp://127.0.0.1:1"), "bridge tcp://127.0.0.1:1");
  EXPECT_EQ(picked(two, "", "", "tcp://10.0.0.9:5"), "(not registered here) tcp://10.0.0.9:5");
  // neither: the only graph running; of several none is guessed, but the one in use is kept
  EXPECT_EQ(picked({two[1]}, ""), "bridge_rt tcp://127.0.0.1:2");
  EXPECT_EQ(picked({}, ""), "none");
  EXPECT_THROW(picked(two, ""), graph::AmbiguousGraph);
  EXPECT_EQ(picked(two, "", "", "", "tcp://127.0.0.1:1"), "bridge tcp://127.0.0.1:1");
  // a process its launcher started: its own graph, among several; a name given still wins
  ASSERT_EQ(setenv("ENACT_ATTACH", "tcp://127.0.0.1:2", 1), 0);
  EXPECT_EQ(picked(two, ""), "bridge_rt tcp://127.0.0.1:2");
  EXPECT_EQ(picked(two, "bridge"), "bridge tcp://127.0.0.1:1");
  unsetenv("ENACT_ATTACH");
}

}  // namespace
}  // namespace enact::test
