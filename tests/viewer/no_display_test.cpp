// The viewer without a display: a live window would be invisible, so it says so and exits 1;
// a snapshot still renders offscreen.
#include <gtest/gtest.h>

#include "tests/support/test_util.h"

namespace enact::test {
namespace {

const std::string kNoDisplay = "env -u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER ";

TEST(ViewerWithoutDisplay, RefusesALiveWindowAndNamesTheFix) {
  const RunResult r = run(kNoDisplay + "timeout 20 " + ENACT_VIEWER + " --attach tcp://127.0.0.1:1");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("no display"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--snapshot"), std::string::npos) << r.err;
}

TEST(ViewerWithoutDisplay, StillTakesASnapshotOffscreen) {
  TempDir dir;
  const RunResult r = run(kNoDisplay + "LP_NUM_THREADS=1 timeout 60 " + ENACT_VIEWER + " --scene " + source_path("launch/scenes/bridge.yaml") +
                          " --attach tcp://127.0.0.1:1 --snapshot " + dir.file("s.png") + " --after 0.2");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(read_file(dir.file("s.png")).size(), 1000u);
}

}  // namespace
}  // namespace enact::test
