// enact installed like a tool (CMakeLists.txt, "Installed like a tool"): `cmake --install`
// of this build into a temporary prefix, then the installed enact, from another working
// directory and with nothing of the build or source tree on its way, answers --help and
// launches the bridge graph by the launch file's relative name, with the installed nodes.
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/test_util.h"

namespace enact::test {
namespace {

bool executable(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && (st.st_mode & S_IXUSR);
}

TEST(Install, TheInstalledEnactRunsTheBridgeGraphFromAnywhere) {
  TempDir prefix, elsewhere;
  const RunResult install = run(std::string("'") + ENACT_CMAKE + "' --install '" + ENACT_BUILD_DIR + "' --prefix '" + prefix.path() + "'");
  ASSERT_EQ(install.exit_code, 0) << install.out << install.err;

  // the executables on one path, the data beside them, the udev rules where udev reads them
  const std::string p = prefix.path();
  for (const char* exe : {"enact", "enact-rt", "enact-sim", "enact-ffd", "enact-tactile", "enact-logger", "enact-foxglove", "enact-bench"}) {
    EXPECT_TRUE(executable(p + "/bin/" + exe)) << exe;
  }
  for (const char* file : {"launch/bridge_rt.yaml", "launch/bridge.yaml", "launch/scenes/bridge.yaml", "launch/paths/bridge_walk.csv",
                           "launch/experiments/bridge.yaml", "foxglove-layout.json"}) {
    EXPECT_TRUE(std::filesystem::is_regular_file(p + "/share/enact/" + file)) << file;
  }
  for (const char* script : {"analyze.py", "psychophysics.py"}) EXPECT_TRUE(executable(p + "/share/enact/scripts/" + script)) << script;
  EXPECT_TRUE(std::filesystem::is_regular_file(p + "/lib/udev/rules.d/99-enact.rules"));

  // from another directory, with only the prefix's bin and the system's on PATH
  const std::string shell = "cd '" + elsewhere.path() + "' && PATH='" + p + "/bin:/usr/bin:/bin' ";
  const RunResult help = run(shell + "enact --help");
  EXPECT_EQ(help.exit_code, 0) << help.err;
  EXPECT_NE(help.out.find("launch FILE"), std::string::npos) << help.out;

  const RunResult launched = run(shell + "enact launch launch/bridge_rt.yaml --duration 1");
  EXPECT_EQ(launched.exit_code, 0) << launched.out << launched.err;
  // the launch file and the container are the installed ones
  EXPECT_NE(launched.err.find("graph ready"), std::string::npos) << launched.err;
  EXPECT_NE(launched.out.find(p + "/bin/enact-rt --name rt"), std::string::npos) << launched.out;
  EXPECT_NE(launched.out.find(p + "/share/enact/launch/scenes/bridge.yaml"), std::string::npos) << launched.out;
  EXPECT_EQ(launched.out.find(ENACT_BUILD_DIR), std::string::npos) << launched.out;
}

// the Debian package of this build: what it installs where (the tools, the data, the scripts,
// the docs, a plugin's headers and CMake package), the runtime libraries it needs declared
// (dpkg-shlibdeps), the scripts' Python recommended
TEST(Install, TheDebianPackageDeclaresItsRuntimeDependencies) {
  if (run("command -v dpkg-deb && command -v dpkg-shlibdeps").exit_code != 0) GTEST_SKIP() << "not a Debian machine (dpkg-dev absent)";
  TempDir out;
  const RunResult pack = run("cd '" + std::string(ENACT_BUILD_DIR) + "' && '" + ENACT_CPACK + "' -G DEB -B '" + out.path() + "'");
  ASSERT_EQ(pack.exit_code, 0) << pack.out << pack.err;
  std::string deb;
  for (const auto& e : std::filesystem::directory_iterator(out.path())) {
    if (e.path().extension() == ".deb") deb = e.path().string();
  }
  ASSERT_NE(deb.find("enact_" + std::string(ENACT_VERSION) + "_"), std::string::npos) << pack.out;
  const RunResult depends = run("dpkg-deb -f '" + deb + "' Depends Recommends");
  ASSERT_EQ(depends.exit_code, 0) << depends.err;
  for (const char* lib : {"libzmq5", "libprotobuf", "libyaml-cpp", "libusb-1.0-0"}) EXPECT_NE(depends.out.find(lib), std::string::npos) << lib << ": " << depends.out;
  EXPECT_NE(depends.out.find("python3-scipy"), std::string::npos) << depends.out;
  const RunResult files = run("dpkg-deb -c '" + deb + "'");
  for (const char* file : {"./usr/bin/enact\n", "./usr/bin/enact-rt\n", "./usr/share/enact/launch/bridge_rt.yaml\n", "./usr/lib/udev/rules.d/99-enact.rules\n",
                           "./usr/share/enact/scripts/power.py\n", "./usr/share/doc/enact/getting-started.md\n",
                           "./usr/include/enact/core/node/loop_component.h\n", "./usr/lib/cmake/enact/enactConfig.cmake\n",
                           "./usr/share/enact/examples/plugins/guide_spring.cpp\n"}) {
    EXPECT_NE(files.out.find(file), std::string::npos) << file;
  }
}

}  // namespace
}  // namespace enact::test
