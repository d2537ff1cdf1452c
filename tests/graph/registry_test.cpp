// The registry of running graphs: what an entry records of its real-time loop, read back by
// the next launcher to place its own loop elsewhere.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <map>
#include <string>

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

}  // namespace
}  // namespace enact::test
