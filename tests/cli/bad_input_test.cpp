// Bad input to `enact`: every refusal exits non-zero and names file:line and the fix.
#include <gtest/gtest.h>

#include <string>

#include "tests/cli/cli_support.h"

namespace enact::test {
namespace {

// the run exits 1 with a message on stderr naming "<file>:<line>:" and a fix
void expect_refused(const RunResult& r, const std::string& file, int line) {
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(file + ":" + std::to_string(line) + ":"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fix:"), std::string::npos) << r.err;
}

class BadScene : public ::testing::Test {
 protected:
  // writes the scene and runs `enact check` on it
  RunResult check(const std::string& text) {
    write_file(scene_, text);
    return enact("check " + scene_);
  }
  TempDir dir_;
  const std::string scene_ = dir_.file("scene.yaml");
};

// an unclosed '[' is reported on the line where it opens, not where the parser noticed
TEST_F(BadScene, UnclosedBracket) {
  const RunResult r = check(
      "scene: bad\n"
      "masses:\n"
      "  - name: m1\n"
      "    mass_kg: 0.01\n"
      "    position_m: [0, 0, 0\n"
      "\n"
      "# anchors\n"
      "\n"
      "fixed:\n"
      "  - {name: f1, position_m: [0, 0, 0]}\n");
  expect_refused(r, scene_, 5);
  EXPECT_NE(r.err.find("malformed YAML"), std::string::npos) << r.err;
}

TEST_F(BadScene, UnknownKeyInAMass) {
  const RunResult r = check(
      "scene: bad\n"
      "masses:\n"
      "  - name: m1\n"
      "    mass_kg: 0.01\n"
      "    position_m: [0, 0, 0.01]\n"
      "    colour: red\n");
  expect_refused(r, scene_, 6);
  EXPECT_NE(r.err.find("colour"), std::string::npos) << r.err;
}

TEST_F(BadScene, NegativeMass) {
  const RunResult r = check(
      "scene: bad\n"
      "masses:\n"
      "  - name: m1\n"
      "    position_m: [0, 0, 0.01]\n"
      "    mass_kg: -0.01\n");
  expect_refused(r, scene_, 5);
  EXPECT_NE(r.err.find("mass_kg"), std::string::npos) << r.err;
}

TEST_F(BadScene, LinkToAnUnknownElement) {
  const RunResult r = check(
      "scene: bad\n"
      "masses:\n"
      "  - {name: m1, mass_kg: 0.01, position_m: [0, 0, 0.01]}\n"
      "fixed:\n"
      "  - {name: f1, position_m: [0, 0, 0]}\n"
      "links:\n"
      "  - name: l1\n"
      "    type: spring\n"
      "    a: m1\n"
      "    b: f2\n"
      "    stiffness_n_per_m: 10\n");
  expect_refused(r, scene_, 10);
  EXPECT_NE(r.err.find("'f2'"), std::string::npos) << r.err;
}

TEST_F(BadScene, UnknownObjectType) {
  const RunResult r = check(
      "scene: bad\n"
      "masses:\n"
      "  - {name: m1, mass_kg: 0.01, position_m: [0, 0, 0.01]}\n"
      "objects:\n"
      "  - name: ball\n"
      "    type: cone\n"
      "    center_m: [0, 0, 0]\n");
  expect_refused(r, scene_, 6);
  EXPECT_NE(r.err.find("cone"), std::string::npos) << r.err;
}

TEST_F(BadScene, MissingFile) {
  const std::string missing = dir_.file("absent.yaml");
  const RunResult r = enact("check " + missing);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fix:"), std::string::npos) << r.err;
}

class BadInput : public ::testing::Test {
 protected:
  // writes the device path and simulates the bridge with it
  RunResult simulate(const std::string& csv) {
    write_file(input_, csv);
    return enact("simulate " + bridge_scene() + " --input " + input_);
  }
  TempDir dir_;
  const std::string input_ = dir_.file("path.csv");
};

TEST_F(BadInput, NaNNamesItsRow) {
  const RunResult r = simulate(
      "t_s,x_m,y_m,z_m\n"
      "0,0,0,0.013\n"
      "0.1,0,0,0.013\n"
      "0.2,nan,0,0.013\n"
      "0.3,0,0,0.013\n");
  expect_refused(r, input_, 4);
}

// the message quotes the row's time, not another column
TEST_F(BadInput, NonIncreasingTimeNamesItsRow) {
  const RunResult r = simulate(
      "t_s,x_m,y_m,z_m\n"
      "0,0,0,0.013\n"
      "0.1,0,0,0.013\n"
      "0.1,0,0,0.013\n");
  expect_refused(r, input_, 4);
  EXPECT_NE(r.err.find("time 0.1 does not increase"), std::string::npos) << r.err;
}

TEST_F(BadInput, MissingFile) {
  const std::string missing = dir_.file("absent.csv");
  const RunResult r = enact("simulate " + bridge_scene() + " --input " + missing);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fix:"), std::string::npos) << r.err;
}

// a 1 g mass on a 1e9 N/m spring at 1 kHz: K = 1e9 N/m against 4M = 4000 N/m
constexpr const char* kUnstable =
    "scene: unstable\n"
    "rate_hz: 1000\n"
    "masses:\n"
    "  - {name: bob, mass_kg: 0.001, position_m: [0.01, 0, 0.01]}\n"
    "fixed:\n"
    "  - {name: anchor, position_m: [0, 0, 0.01]}\n"
    "links:\n"
    "  - {name: stiff, type: spring, a: bob, b: anchor, stiffness_n_per_m: 1.0e9}\n"
    "body:\n"
    "  name: finger\n"
    "  position_m: [0, 0, 0.05]\n";

class UnstableScene : public ::testing::Test {
 protected:
  void SetUp() override {
    write_file(scene_, kUnstable);
    write_file(input_, "t_s,x_m,y_m,z_m\n0,0,0,0.05\n0.5,0.01,0,0.05\n");
  }
  TempDir dir_;
  const std::string scene_ = dir_.file("unstable.yaml");
  const std::string input_ = dir_.file("line.csv");
};

TEST_F(UnstableScene, CheckExitsOneNamingTheElement) {
  const RunResult r = enact("check " + scene_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("UNSTABLE"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find(scene_ + ":4:"), std::string::npos) << r.err;  // the mass's line
  EXPECT_NE(r.err.find("'bob'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'stiff'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fix:"), std::string::npos) << r.err;
}

TEST_F(UnstableScene, SimulateRefusesItWithoutForce) {
  const RunResult r = enact("simulate " + scene_ + " --input " + input_);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
}

TEST_F(UnstableScene, SimulateForceRunsItAndCountsFaults) {
  const std::string metrics = dir_.file("m.json");
  const RunResult r = enact("simulate " + scene_ + " --input " + input_ + " --force --metrics " + metrics);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string json = read_file(metrics);
  EXPECT_EQ(json_value(json, "steps"), "501") << json;
  EXPECT_NE(json_value(json, "faults"), "0") << json;  // the divergence guard caught it
  EXPECT_FALSE(json_value(json, "faults").empty()) << json;
}

// `enact keys` and `enact launch --access`: wrong arguments exit 2, bad files 1 with file:line
class KeysAndAccess : public ::testing::Test {
 protected:
  TempDir dir_;
};

TEST_F(KeysAndAccess, KeysNewWritesAPairOnceAndShowPrintsItsPublicKey) {
  const RunResult made = enact("keys new lab --dir " + dir_.path());
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const RunResult shown = enact("keys show " + dir_.file("lab.key"));
  EXPECT_EQ(shown.exit_code, 0) << shown.err;
  EXPECT_EQ(shown.out, enact("keys show " + dir_.file("lab.pub")).out);
  EXPECT_EQ(shown.out.size(), 41u) << shown.out;
  EXPECT_NE(made.out.find(shown.out.substr(0, 40)), std::string::npos) << made.out;
  const RunResult again = enact("keys new lab --dir " + dir_.path());
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("never overwritten"), std::string::npos) << again.err;
  EXPECT_EQ(enact("keys new").exit_code, 2);
  EXPECT_EQ(enact("keys frobnicate x").exit_code, 2);
  EXPECT_EQ(enact("keys show " + dir_.file("none.pub")).exit_code, 1);
}

TEST_F(KeysAndAccess, LaunchRefusesRemoteWithoutAccessAndABadAccessFile) {
  const std::string launch = source_path("launch/bridge_rt.yaml");
  const RunResult remote = enact("launch " + launch + " --attach 'tcp://*:0' --allow-remote");
  EXPECT_EQ(remote.exit_code, 2);
  EXPECT_NE(remote.err.find("--access"), std::string::npos) << remote.err;
  ASSERT_EQ(enact("keys new graph --dir " + dir_.path()).exit_code, 0);
  write_file(dir_.file("access.yaml"), "server_key: graph.key\nclients:\n  - {name: x, public_key: short, role: observe}\n");
  expect_refused(enact("launch " + launch + " --access " + dir_.file("access.yaml")), dir_.file("access.yaml"), 3);
}

}  // namespace
}  // namespace enact::test
