// The one lookup of shipped files (core/config/share.h): a path as written where the user
// stands (or beside the file naming it), else in enact's share, here the source tree of this
// build (this test runs from the build); a file found nowhere is refused with every place
// looked in. $(share) in a launch file is the same folder. The installed share is tested end
// to end by tests/install/installed_tour.sh (InstalledTour).
#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/config/share.h"
#include "core/config/yaml.h"
#include "core/launch/launch_file.h"
#include "tests/support/test_util.h"

namespace enact::test {
namespace {

namespace fs = std::filesystem;

// the working directory moved to `to` while it lives
class WorkIn {
 public:
  explicit WorkIn(const std::string& to) : was_(fs::current_path()) { fs::current_path(to); }
  ~WorkIn() { fs::current_path(was_); }

 private:
  fs::path was_;
};

std::string source(const std::string& relative) { return fs::path(source_path(relative)).lexically_normal().string(); }

TEST(Share, AShippedFileIsFoundFromAnotherFolderInTheSourceTreeOfThisBuild) {
  TempDir elsewhere;
  WorkIn here(elsewhere.path());
  ASSERT_FALSE(config::share_roots().empty());
  EXPECT_EQ(config::share_roots().back().data, ENACT_SOURCE_DIR);
  EXPECT_EQ(config::share_dir(), ENACT_SOURCE_DIR) << "a build's enact has no installed share beside it";
  EXPECT_EQ(config::find_file("launch/scenes/bridge.yaml"), source("launch/scenes/bridge.yaml"));
  EXPECT_EQ(config::shipped("scripts/power.py"), source("scripts/power.py"));
  EXPECT_EQ(config::shipped("docs/scenes-and-models.md"), source("docs/scenes-and-models.md"));
  EXPECT_EQ(config::shipped("core/node/loop_component.h"), source("core/node/loop_component.h"));
  EXPECT_EQ(config::shipped("scripts/nothing.py"), "scripts/nothing.py") << "a hint keeps what no root has as written";
}

TEST(Share, TheUsersOwnFileWhereTheyStandComesFirstAsWritten) {
  TempDir mine;
  fs::create_directories(mine.file("launch/scenes"));
  write_file(mine.file("launch/scenes/bridge.yaml"), "scene: mine\n");
  WorkIn here(mine.path());
  EXPECT_EQ(config::find_file("launch/scenes/bridge.yaml"), "launch/scenes/bridge.yaml");
  EXPECT_EQ(config::shipped("launch/scenes/bridge.yaml"), "launch/scenes/bridge.yaml");
}

TEST(Share, APathNamedInAFileIsLookedForBesideItThenInTheShareNotWhereTheUserStands) {
  TempDir dir;
  fs::create_directories(dir.file("exp/launch/scenes"));
  fs::create_directories(dir.file("cwd/paths"));
  const std::string naming = dir.file("exp/mine.yaml");
  write_file(naming, "graph: x\n");
  write_file(dir.file("exp/launch/scenes/bridge.yaml"), "scene: beside\n");
  write_file(dir.file("cwd/paths/own.csv"), "t_s,x_m,y_m,z_m\n");
  WorkIn here(dir.file("cwd"));
  EXPECT_EQ(config::find_file("launch/scenes/bridge.yaml", naming), dir.file("exp/launch/scenes/bridge.yaml"));
  EXPECT_EQ(config::find_file("launch/scenes/ridge.yaml", naming), source("launch/scenes/ridge.yaml"));
  EXPECT_FALSE(config::locate("paths/own.csv", naming)) << "a file names paths relative to itself, not to where enact runs";
  EXPECT_EQ(*config::locate("paths/own.csv"), "paths/own.csv");
}

TEST(Share, AFileFoundNowhereIsRefusedWithEveryPlaceLookedIn) {
  TempDir elsewhere;
  WorkIn here(elsewhere.path());
  try {
    config::find_file("launch/scenes/nowhere.yaml");
    FAIL() << "no error";
  } catch (const config::Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("launch/scenes/nowhere.yaml: cannot open the file\n", 0), 0u) << what;
    EXPECT_NE(what.find("looked in " + elsewhere.file("launch/scenes/nowhere.yaml") + " (the current directory)"), std::string::npos) << what;
    EXPECT_NE(what.find("looked in " + source("launch/scenes/nowhere.yaml") + " (the source tree of this build)"), std::string::npos) << what;
    EXPECT_NE(what.find("fix: check the path"), std::string::npos) << what;
  }
  // the loaders take the same lookup: the error is the scene's, with the places
  try {
    config::find_file("/no/such/scene.yaml");
    FAIL() << "no error";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("looked in /no/such/scene.yaml\n"), std::string::npos) << e.what();
  }
}

TEST(Share, ALaunchFileAnywhereNamesShippedFilesWithShareAndIsFoundByItsShippedName) {
  TempDir elsewhere;
  WorkIn here(elsewhere.path());
  write_file(elsewhere.file("mine.yaml"),
             "launch:\n"
             "  - container:\n"
             "      name: rt\n"
             "      component:\n"
             "        - {name: sim, plugin: sim, param: [{name: scene, value: \"$(share)/launch/scenes/bridge.yaml\"}]}\n"
             "  - include: {file: launch/bridge_rt.yaml}\n");
  // the include (not beside mine.yaml) is read from the share: its container rt is a second one
  try {
    launch::load_launch("mine.yaml", {}, [](const std::string& e) { return e; });
    FAIL() << "no error";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("two nodes are named 'rt'"), std::string::npos) << e.what();
  }
  write_file(elsewhere.file("mine.yaml"),
             "launch:\n"
             "  - container:\n"
             "      name: guided\n"
             "      component:\n"
             "        - {name: sim, plugin: sim, param: [{name: scene, value: \"$(share)/launch/scenes/bridge.yaml\"}]}\n");
  const launch::LaunchDescription d = launch::load_launch("mine.yaml", {}, [](const std::string& e) { return e; });
  ASSERT_EQ(d.nodes.size(), 1u);
  ASSERT_EQ(d.nodes[0].components.size(), 1u);
  ASSERT_EQ(d.nodes[0].components[0].params.size(), 1u);
  EXPECT_EQ(d.nodes[0].components[0].params[0].value, std::string(ENACT_SOURCE_DIR) + "/launch/scenes/bridge.yaml");
  // a shipped launch file by its name in enact's tree, from here
  const launch::LaunchDescription shipped = launch::load_launch("launch/bridge_rt.yaml", {{"scene", "launch/scenes/two_boxes.yaml"}},
                                                                [](const std::string& e) { return e; });
  EXPECT_FALSE(shipped.nodes.empty());
}

}  // namespace
}  // namespace enact::test
