// Folders of graphs whose launcher died are removed by the next launch; live ones are kept.
#include "core/launch/stale_graphs.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/test_util.h"

namespace enact::launch {
namespace {

namespace fs = std::filesystem;

// a pid that surely names no process: a child that exited and was reaped
pid_t dead_pid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  waitpid(pid, nullptr, 0);
  return pid;
}

TEST(StaleGraphs, FoldersOfDeadLaunchersAreRemovedOthersKept) {
  test::TempDir dir;
  const fs::path root = dir.path();
  // a dead launcher's folder (with a socket file in it), a live one's, one without a pid
  // file (not ours to judge) and a folder of another name with a dead pid
  fs::create_directories(root / "enact-graph-dead");
  std::ofstream(root / "enact-graph-dead" / kLauncherPidFile) << dead_pid() << "\n";
  std::ofstream(root / "enact-graph-dead" / "sim.sock") << "";
  fs::create_directories(root / "enact-graph-live");
  mark_graph_folder((root / "enact-graph-live").string());
  fs::create_directories(root / "enact-graph-unknown");
  fs::create_directories(root / "other-dead");
  std::ofstream(root / "other-dead" / kLauncherPidFile) << dead_pid() << "\n";

  EXPECT_EQ(remove_stale_graph_folders(root.string(), "enact-graph-"), 1);
  EXPECT_FALSE(fs::exists(root / "enact-graph-dead"));
  EXPECT_TRUE(fs::exists(root / "enact-graph-live"));
  EXPECT_TRUE(fs::exists(root / "enact-graph-unknown"));
  EXPECT_TRUE(fs::exists(root / "other-dead"));
}

}  // namespace
}  // namespace enact::launch
