// Loading launch files: arguments, substitutions, includes, params, containers, and every
// refusal naming file:line and the fix, before anything starts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/config/yaml.h"
#include "core/launch/launch_file.h"
#include "tests/support/test_util.h"
#include "tests/support/refusal.h"

namespace enact::launch {
namespace {

using test::TempDir;
using test::write_file;
using Overrides = std::map<std::string, std::string>;

// a path (with '/') as given, a bare name under /opt/enact/bin, any name with "missing": not found
std::string fake_resolve(const std::string& exec) {
  if (exec.find("missing") != std::string::npos) return "";
  return exec.find('/') != std::string::npos ? exec : "/opt/enact/bin/" + exec;
}

bool contains(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

std::string param(const NodeSpec& n, const std::string& name) {
  for (const Param& p : n.params) {
    if (p.name == name) return p.value;
  }
  return "<absent>";
}

class LoadLaunch : public ::testing::Test {
 protected:
  // writes dir/name and returns its path
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = dir_.file(name);
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    write_file(path, text);
    return path;
  }
  LaunchDescription load(const std::string& name, const Overrides& args = {}) {
    return load_launch(dir_.file(name), args, fake_resolve);
  }
  // the message of the refusal, "" when the file loads
  std::string refusal(const std::string& name, const Overrides& args = {}) {
    return test::error_of([&] { load(name, args); });
  }
  // the refusal names "<file>:<line>:" and a fix
  void expect_refused_at(const std::string& name, int line, const Overrides& args = {}) {
    const std::string msg = refusal(name, args);
    EXPECT_NE(msg.find(dir_.file(name) + ":" + std::to_string(line) + ":"), std::string::npos) << msg;
    EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
  }
  TempDir dir_;
};

constexpr const char* kArgs =
    "launch:\n"
    "  - arg: {name: rate, default: '100', description: loop rate}\n"
    "  - arg: {name: device, default: sim}\n"
    "  - node:\n"
    "      name: ctl\n"
    "      exec: ctl\n"
    "      param:\n"
    "        - {name: rate_hz, value: $(var rate)}\n"
    "        - {name: device, value: dev-$(var device)}\n";

TEST_F(LoadLaunch, ArgsTakeTheirDefaults) {
  write("a.yaml", kArgs);
  const LaunchDescription d = load("a.yaml");
  ASSERT_EQ(d.args.size(), 2u);
  EXPECT_EQ(d.args[0].name, "rate");
  EXPECT_EQ(d.args[0].value, "100");
  EXPECT_EQ(d.args[0].description, "loop rate");
  ASSERT_EQ(d.nodes.size(), 1u);
  EXPECT_EQ(param(d.nodes[0], "rate_hz"), "100");
  EXPECT_EQ(param(d.nodes[0], "device"), "dev-sim");
}

TEST_F(LoadLaunch, ArgOverrideWins) {
  write("a.yaml", kArgs);
  const LaunchDescription d = load("a.yaml", {{"rate", "250"}});
  EXPECT_EQ(d.args[0].value, "250");
  EXPECT_EQ(param(d.nodes[0], "rate_hz"), "250");
  EXPECT_EQ(param(d.nodes[0], "device"), "dev-sim");
}

TEST_F(LoadLaunch, UndeclaredOverrideIsRefusedListingTheDeclaredOnes) {
  write("a.yaml", kArgs);
  const std::string msg = refusal("a.yaml", {{"rat", "5"}});
  EXPECT_NE(msg.find("'rat'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("rate"), std::string::npos) << msg;
  EXPECT_NE(msg.find("device"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

TEST_F(LoadLaunch, ArgWithoutDefaultMustBeGiven) {
  write("a.yaml",
        "launch:\n"
        "  - arg: {name: port}\n"
        "  - node: {name: n, exec: tool, param: [{name: port, value: $(var port)}]}\n");
  const std::string msg = refusal("a.yaml");
  EXPECT_NE(msg.find(dir_.file("a.yaml") + ":2:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'port'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("--arg port="), std::string::npos) << msg;
  EXPECT_EQ(param(load("a.yaml", {{"port", "/dev/ttyACM0"}}).nodes[0], "port"), "/dev/ttyACM0");
}

TEST_F(LoadLaunch, EnvAndDirnameSubstitutions) {
  if (!std::getenv("HOME")) setenv("HOME", "/home/test", 1);
  unsetenv("ENACT_TEST_UNSET_VAR");
  write("a.yaml",
        "launch:\n"
        "  - node:\n"
        "      name: n\n"
        "      exec: tool\n"
        "      param:\n"
        "        - {name: home, value: $(env HOME)}\n"
        "        - {name: fallback, value: $(env ENACT_TEST_UNSET_VAR fallback-value)}\n"
        "        - {name: here, value: $(dirname)/scenes/x.yaml}\n");
  const NodeSpec n = load("a.yaml").nodes.at(0);
  EXPECT_EQ(param(n, "home"), std::getenv("HOME"));
  EXPECT_EQ(param(n, "fallback"), "fallback-value");
  EXPECT_EQ(param(n, "here"), dir_.path() + "/scenes/x.yaml");
}

TEST_F(LoadLaunch, UnsetEnvWithoutDefaultIsRefused) {
  unsetenv("ENACT_TEST_UNSET_VAR");
  write("a.yaml",
        "launch:\n"
        "  - node:\n"
        "      name: n\n"
        "      exec: tool\n"
        "      param: [{name: x, value: $(env ENACT_TEST_UNSET_VAR)}]\n");
  expect_refused_at("a.yaml", 5);
  EXPECT_NE(refusal("a.yaml").find("ENACT_TEST_UNSET_VAR"), std::string::npos);
}

TEST_F(LoadLaunch, UnknownSubstitutionIsRefusedAtItsLine) {
  write("a.yaml",
        "launch:\n"
        "  - node:\n"
        "      name: n\n"
        "      exec: tool\n"
        "      param:\n"
        "        - {name: scene, value: $(find-pkg-share enact)/x.yaml}\n");
  expect_refused_at("a.yaml", 6);
  EXPECT_NE(refusal("a.yaml").find("find-pkg-share"), std::string::npos);
}

TEST_F(LoadLaunch, IncludePassesArgsAndExpandsInPlace) {
  write("sub/inner.yaml",
        "launch:\n"
        "  - arg: {name: who}\n"
        "  - arg: {name: unused, default: u}\n"
        "  - node:\n"
        "      name: inner\n"
        "      exec: tool\n"
        "      param:\n"
        "        - {name: who, value: $(var who)}\n"
        "        - {name: here, value: $(dirname)}\n");
  write("top.yaml",
        "launch:\n"
        "  - arg: {name: name, default: alice}\n"
        "  - node: {name: first, exec: tool}\n"
        "  - include:\n"
        "      file: sub/inner.yaml\n"
        "      arg: [{name: who, value: $(var name)}]\n"
        "  - node: {name: last, exec: tool}\n");
  const LaunchDescription d = load("top.yaml", {{"name", "bob"}});
  ASSERT_EQ(d.nodes.size(), 3u);
  EXPECT_EQ(d.nodes[0].name, "first");
  EXPECT_EQ(d.nodes[1].name, "inner");
  EXPECT_EQ(d.nodes[2].name, "last");
  EXPECT_EQ(param(d.nodes[1], "who"), "bob");
  EXPECT_EQ(param(d.nodes[1], "here"), dir_.path() + "/sub");
  // only the top file's args are the launch's args
  ASSERT_EQ(d.args.size(), 1u);
  EXPECT_EQ(d.args[0].name, "name");
}

TEST_F(LoadLaunch, IncludeOfAnUndeclaredArgIsRefused) {
  write("inner.yaml", "launch:\n  - node: {name: inner, exec: tool}\n");
  write("top.yaml",
        "launch:\n"
        "  - include: {file: inner.yaml, arg: [{name: nope, value: '1'}]}\n");
  const std::string msg = refusal("top.yaml");
  EXPECT_NE(msg.find("nope"), std::string::npos) << msg;
}

TEST_F(LoadLaunch, IncludeCycleIsRefused) {
  write("a.yaml",
        "launch:\n"
        "  - include: {file: b.yaml}\n"
        "  - node: {name: n, exec: tool}\n");
  write("b.yaml", "launch:\n  - include: {file: a.yaml}\n");
  const std::string msg = refusal("a.yaml");
  EXPECT_NE(msg.find("includes"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

TEST_F(LoadLaunch, SelfIncludeAfterANodeIsRefused) {
  write("a.yaml",
        "launch:\n"
        "  - node: {name: n, exec: tool}\n"
        "  - include: {file: a.yaml}\n");
  EXPECT_NE(refusal("a.yaml"), "");
}

TEST_F(LoadLaunch, ParamOverridesParamFile) {
  write("cfg/params.yaml", "stiffness_n_per_m: 500\ndamping: 2\nmode: soft\n");
  write("a.yaml",
        "launch:\n"
        "  - node:\n"
        "      name: n\n"
        "      exec: tool\n"
        "      param_file: cfg/params.yaml\n"
        "      param:\n"
        "        - {name: damping, value: 3}\n"
        "        - {name: extra, value: x}\n");
  const NodeSpec n = load("a.yaml").nodes.at(0);
  ASSERT_EQ(n.params.size(), 4u);
  EXPECT_EQ(param(n, "stiffness_n_per_m"), "500");
  EXPECT_EQ(param(n, "damping"), "3");
  EXPECT_EQ(param(n, "mode"), "soft");
  EXPECT_EQ(param(n, "extra"), "x");
  EXPECT_TRUE(contains(n.argv(), "--param=damping=3"));
  EXPECT_FALSE(contains(n.argv(), "--param=damping=2"));
}

TEST_F(LoadLaunch, EnvArgsAndFlags) {
  write("a.yaml",
        "launch:\n"
        "  - node:\n"
        "      name: listed\n"
        "      exec: tool\n"
        "      args: [-v, 'two words']\n"
        "      env: [{name: LEVEL, value: debug}]\n"
        "      respawn: true\n"
        "      respawn_delay: 0.25\n"
        "  - node:\n"
        "      name: split\n"
        "      exec: ./bin/tool\n"
        "      args: '--fast  --mode x'\n"
        "      required: true\n");
  const LaunchDescription d = load("a.yaml");
  const NodeSpec& listed = d.nodes.at(0);
  EXPECT_EQ(listed.args, (std::vector<std::string>{"-v", "two words"}));
  ASSERT_EQ(listed.env.size(), 1u);
  EXPECT_EQ(listed.env[0].name, "LEVEL");
  EXPECT_EQ(listed.env[0].value, "debug");
  EXPECT_TRUE(listed.respawn);
  EXPECT_FALSE(listed.required);
  EXPECT_DOUBLE_EQ(listed.respawn_delay_s, 0.25);
  EXPECT_EQ(listed.path, "/opt/enact/bin/tool");
  EXPECT_EQ(listed.source, dir_.file("a.yaml") + ":3");
  EXPECT_EQ(listed.argv(), (std::vector<std::string>{"/opt/enact/bin/tool", "-v", "two words", "--name", "listed"}));
  const NodeSpec& split = d.nodes.at(1);
  EXPECT_EQ(split.args, (std::vector<std::string>{"--fast", "--mode", "x"}));
  EXPECT_TRUE(split.required);
  EXPECT_FALSE(split.respawn);
  // a relative path is relative to the launch file's folder
  EXPECT_EQ(std::filesystem::path(split.path).lexically_normal(), dir_.path() + "/bin/tool");
}

TEST_F(LoadLaunch, DefaultResolverFindsAPathNextToTheFile) {
  write("bin/tool.sh", "#!/bin/sh\n");
  std::filesystem::permissions(dir_.file("bin/tool.sh"), std::filesystem::perms::owner_all);
  write("a.yaml", "launch:\n  - node: {name: n, exec: bin/tool.sh}\n");
  EXPECT_EQ(load_launch(dir_.file("a.yaml"), {}).nodes.at(0).path, dir_.path() + "/bin/tool.sh");
  write("b.yaml", "launch:\n  - node: {name: n, exec: bin/absent.sh}\n");
  EXPECT_THROW(load_launch(dir_.file("b.yaml"), {}), config::Error);
}

TEST_F(LoadLaunch, ContainerComponentsBecomeFlags) {
  write("a.yaml",
        "launch:\n"
        "  - arg: {name: scene, default: bridge.yaml}\n"
        "  - container:\n"
        "      name: rt\n"
        "      component:\n"
        "        - name: sim\n"
        "          plugin: sim\n"
        "          param: [{name: scene, value: $(dirname)/$(var scene)}]\n"
        "        - {name: ffd, plugin: ffd, param: [{name: port, value: /dev/ttyACM0}]}\n");
  const NodeSpec n = load("a.yaml").nodes.at(0);
  EXPECT_TRUE(n.container);
  EXPECT_EQ(n.exec, "enact-rt");
  EXPECT_EQ(n.path, "/opt/enact/bin/enact-rt");
  ASSERT_EQ(n.components.size(), 2u);
  const std::vector<std::string> argv = n.argv();
  EXPECT_TRUE(contains(argv, "--component=sim:sim"));
  EXPECT_TRUE(contains(argv, "--component=ffd:ffd"));
  EXPECT_TRUE(contains(argv, "--param=sim.scene=" + dir_.path() + "/bridge.yaml"));
  EXPECT_TRUE(contains(argv, "--param=ffd.port=/dev/ttyACM0"));
}

// a container that names no components hosts the default three, named as their plugins, its
// own parameters scoped as theirs would be; an empty list is refused
TEST_F(LoadLaunch, ContainerWithoutComponentsHostsTheDefaultThree) {
  write("a.yaml", "launch:\n  - container: {name: rt, param: [{name: sim.model, value: CM3}]}\n");
  const NodeSpec n = load("a.yaml").nodes.at(0);
  ASSERT_EQ(n.components.size(), 3u);
  const std::vector<std::string> argv = n.argv();
  for (const char* plugin : kDefaultComponents) {
    EXPECT_TRUE(contains(argv, std::string("--component=") + plugin + ":" + plugin)) << plugin;
  }
  EXPECT_TRUE(contains(argv, "--param=sim.model=CM3"));
  write("b.yaml", "launch:\n  - container: {name: rt, component: []}\n");
  EXPECT_NE(refusal("b.yaml").find("empty component list"), std::string::npos);
  expect_refused_at("b.yaml", 2);
}

TEST_F(LoadLaunch, RequiredAndRespawnTogetherAreRefused) {
  write("a.yaml",
        "launch:\n"
        "  - node:\n"
        "      name: n\n"
        "      exec: tool\n"
        "      required: true\n"
        "      respawn: true\n");
  expect_refused_at("a.yaml", 6);
}

TEST_F(LoadLaunch, DuplicateNodeNamesAreRefused) {
  write("a.yaml",
        "launch:\n"
        "  - node: {name: twin, exec: tool}\n"
        "  - node:\n"
        "      name: twin\n"
        "      exec: other\n");
  expect_refused_at("a.yaml", 4);
  EXPECT_NE(refusal("a.yaml").find("'twin'"), std::string::npos);
}

TEST_F(LoadLaunch, UnknownKeyInANodeIsRefusedAtTheKey) {
  write("a.yaml",
        "launch:\n"
        "  - node:\n"
        "      name: n\n"
        "      exec: tool\n"
        "\n"
        "      respwan: true\n");
  expect_refused_at("a.yaml", 6);
  const std::string msg = refusal("a.yaml");
  EXPECT_NE(msg.find("respwan"), std::string::npos) << msg;
  EXPECT_NE(msg.find("respawn"), std::string::npos) << msg;  // the fix lists the known keys
}

TEST_F(LoadLaunch, WrongTypeIsRefused) {
  write("a.yaml",
        "launch:\n"
        "  - node:\n"
        "      name: n\n"
        "      exec: tool\n"
        "      required: maybe\n");
  expect_refused_at("a.yaml", 5);
  EXPECT_NE(refusal("a.yaml").find("maybe"), std::string::npos);
}

TEST_F(LoadLaunch, MissingExecutableIsRefusedAtTheExecLine) {
  write("a.yaml",
        "launch:\n"
        "  - node: {name: ok, exec: tool}\n"
        "  - node:\n"
        "      name: n\n"
        "      exec: missing-tool\n");
  expect_refused_at("a.yaml", 5);
  EXPECT_NE(refusal("a.yaml").find("missing-tool"), std::string::npos);
}

TEST_F(LoadLaunch, EmptyLaunchIsRefused) {
  write("empty.yaml", "launch: []\n");
  EXPECT_NE(refusal("empty.yaml").find("no node"), std::string::npos) << refusal("empty.yaml");
  write("args-only.yaml", "launch:\n  - arg: {name: a, default: x}\n");
  EXPECT_NE(refusal("args-only.yaml").find("fix:"), std::string::npos);
}

TEST_F(LoadLaunch, UnknownEntryIsRefused) {
  write("a.yaml",
        "launch:\n"
        "  - node: {name: n, exec: tool}\n"
        "  - group: {name: g}\n");
  expect_refused_at("a.yaml", 3);
}

TEST_F(LoadLaunch, MalformedYamlIsRefusedWithALine) {
  write("a.yaml",
        "launch:\n"
        "  - node: {name: n, exec: tool\n"
        "  - node: {name: m, exec: tool}\n");
  const std::string msg = refusal("a.yaml");
  EXPECT_NE(msg.find("malformed YAML"), std::string::npos) << msg;
  expect_refused_at("a.yaml", 2);
}

TEST_F(LoadLaunch, MissingFileIsRefused) {
  EXPECT_NE(refusal("absent.yaml").find("cannot open"), std::string::npos);
}

constexpr const char* kRealtime =
    "launch:\n"
    "  - arg: {name: fifo, default: '0'}\n"
    "  - realtime: {loop: [ffd, sim], fifo_priority: $(var fifo)}\n"
    "  - node: {name: sim, exec: sim}\n"
    "  - node: {name: ffd, exec: ffd}\n";

TEST_F(LoadLaunch, RealtimeEntryNamesTheLoopAndItsPriority) {
  write("a.yaml", kRealtime);
  const LaunchDescription d = load("a.yaml", {{"fifo", "80"}});
  EXPECT_TRUE(d.realtime.enabled);
  EXPECT_TRUE(d.realtime.cpu_latency);
  EXPECT_EQ(d.realtime.loop, (std::vector<std::string>{"ffd", "sim"}));
  EXPECT_EQ(d.realtime.fifo_priority, 80);
  // without the entry the profile is off
  write("b.yaml", kArgs);
  EXPECT_FALSE(load("b.yaml").realtime.enabled);
}

TEST_F(LoadLaunch, RealtimeRefusesAnUnknownLoopNodeAndAnUnorderablePriority) {
  write("a.yaml", kRealtime);
  expect_refused_at("a.yaml", 3, {{"fifo", "2"}});
  expect_refused_at("a.yaml", 3, {{"fifo", "high"}});
  write("b.yaml",
        "launch:\n"
        "  - node: {name: sim, exec: sim}\n"
        "  - realtime: {loop: [ffd, sim]}\n");
  expect_refused_at("b.yaml", 3);
  EXPECT_NE(refusal("b.yaml").find("'ffd'"), std::string::npos);
}

TEST_F(LoadLaunch, ClockEntryChoosesTheGraphClockAndTheCommandLineOverridesIt) {
  write("a.yaml",
        "launch:\n"
        "  - arg: {name: clock, default: real}\n"
        "  - clock: $(var clock)\n"
        "  - node: {name: sim, exec: sim}\n");
  EXPECT_EQ(load("a.yaml").clock, rt::GraphClock::real);
  LaunchDescription d = load("a.yaml", {{"clock", "simulated"}});
  EXPECT_EQ(d.clock, rt::GraphClock::simulated);
  EXPECT_NE(d.clock_source.find("a.yaml:3"), std::string::npos) << d.clock_source;
  choose_clock(d, rt::GraphClock::real);
  EXPECT_EQ(d.clock, rt::GraphClock::real);
  EXPECT_EQ(d.clock_source, "--clock");
  // without the entry: real time
  write("b.yaml", kArgs);
  EXPECT_EQ(load("b.yaml").clock, rt::GraphClock::real);
  // a clock that is neither, and a second entry, are refused at their line
  expect_refused_at("a.yaml", 3, {{"clock", "fast"}});
  write("c.yaml",
        "launch:\n"
        "  - clock: simulated\n"
        "  - clock: real\n"
        "  - node: {name: sim, exec: sim}\n");
  expect_refused_at("c.yaml", 3);
}

TEST_F(LoadLaunch, ShippedGraphsHoldTheRealtimeProfileByDefault) {
  for (const char* file : {"bridge.yaml", "bridge_rt.yaml", "experiments/trial.yaml", "experiments/trial_rt.yaml"}) {
    const LaunchDescription d = load_launch(std::string(ENACT_SOURCE_DIR) + "/launch/" + file, {}, fake_resolve);
    EXPECT_TRUE(d.realtime.enabled) << file;
    EXPECT_FALSE(d.realtime.loop.empty()) << file;
    EXPECT_EQ(d.realtime.fifo_priority, 80) << file;
    EXPECT_EQ(load_launch(std::string(ENACT_SOURCE_DIR) + "/launch/" + file, {{"fifo_priority", "0"}}, fake_resolve).realtime.fifo_priority, 0) << file;
  }
}

// $(recorded ARG NAME): the recorded simulator's parameter, by the lookup the program gives,
// from the recording the argument names; overridden by --arg, refused without a lookup
TEST_F(LoadLaunch, RecordedSubstitutesTheRecordingsParameter) {
  write("replay.yaml",
        "launch:\n"
        "  - arg: {name: recording}\n"
        "  - arg: {name: scene, default: \"$(recorded recording scene)\"}\n"
        "  - node:\n"
        "      name: sim\n"
        "      exec: enact-sim\n"
        "      param: [{name: scene, value: $(var scene)}]\n");
  set_recorded_lookup({});
  const std::string none = refusal("replay.yaml", {{"recording", "run.mcap"}});
  EXPECT_NE(none.find("replay.yaml:3: $(recorded ...) needs a program that reads recordings"), std::string::npos) << none;
  std::vector<std::string> asked;
  set_recorded_lookup([&](const std::string& recording, const std::string& name) {
    asked.push_back(recording + " " + name);
    return "/tmp/copy/" + name + ".yaml";
  });
  EXPECT_EQ(param(load("replay.yaml", {{"recording", "run.mcap"}}).nodes[0], "scene"), "/tmp/copy/scene.yaml");
  EXPECT_EQ(asked, std::vector<std::string>{"run.mcap scene"});
  EXPECT_EQ(param(load("replay.yaml", {{"recording", "run.mcap"}, {"scene", "mine.yaml"}}).nodes[0], "scene"), "mine.yaml");
  EXPECT_EQ(asked.size(), 1u) << "a default given over is not evaluated";
  write("bad.yaml", "launch:\n  - arg: {name: scene, default: \"$(recorded nothing scene)\"}\n");
  expect_refused_at("bad.yaml", 2);
  set_recorded_lookup({});
}

}  // namespace
}  // namespace enact::launch
