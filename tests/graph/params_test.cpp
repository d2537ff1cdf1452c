// Node parameters from the command line: typed, checked, typos refused with the fix.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "core/config/format.h"
#include "core/config/yaml.h"
#include "core/devices/simulated_tactile.h"
#include "core/node/components.h"
#include "core/params/node_params.h"
#include "core/params/params.h"
#include "core/sim/simulator.h"
#include "tests/support/refusal.h"
#include "tests/support/test_util.h"

namespace enact::graph {
namespace {

NodeArgs parse(std::vector<std::string> words) {
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  return parse_node_args(static_cast<int>(argv.size()), argv.data(), "node");
}

using test::error_of;

TEST(NodeArgs, NameParamsAndComponents) {
  const NodeArgs a = parse({"enact-rt", "--name", "rt", "--component=sim:sim", "--param=sim.scene=s.yaml", "--param", "rate_hz=44000"});
  EXPECT_EQ(a.name, "rt");
  ASSERT_EQ(a.components.size(), 1u);
  EXPECT_EQ(a.components[0].first, "sim");
  a.params.declare(*node_table("enact-rt"));
  EXPECT_EQ(a.params.number("rate_hz"), 44000.0);
  const Params sim = a.params.scoped("sim");
  EXPECT_EQ(sim_params(sim).scene, "s.yaml");
}

TEST(NodeArgs, UnknownArgumentIsRefused) {
  const std::string msg = error_of([] { parse({"x", "--rate", "5"}); });
  EXPECT_NE(msg.find("--rate"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

TEST(Params, TypesAreCheckedWhenDeclared) {
  auto refusal = [](const std::string& name, ParamType type, const std::string& value) {
    Params p("ffd");
    p.set(name, value);
    ParamSpec spec;
    spec.name = name;
    spec.type = type;
    return error_of([&] { p.declare({spec}); });
  };
  EXPECT_NE(refusal("k", ParamType::number, "abc").find("'k' must be a finite number"), std::string::npos);
  EXPECT_NE(refusal("on", ParamType::flag, "maybe").find("true or false"), std::string::npos);
  EXPECT_NE(refusal("v", ParamType::vec3, "1,2").find("x,y,z"), std::string::npos);
  EXPECT_EQ(refusal("v", ParamType::vec3, "0.1,0,-2e-3"), "");
}

TEST(Params, ReadsGiveTheDeclaredDefaultAndRefuseAnUndeclaredName) {
  Params p("tactile");
  p.set("rows", "2");
  p.declare(tactile_table());
  EXPECT_EQ(p.integer("rows"), 2);
  EXPECT_EQ(p.number("rise_time_s"), devices::SimulatedTactileParams{}.rise_time_s);
  EXPECT_THROW(p.number("not_declared_s"), std::logic_error);
}

TEST(Params, ATypoIsRefusedWithDidYouMean) {
  Params p("tactile");
  p.set("rise_time", "0.02");  // should be rise_time_s
  const std::string msg = error_of([&] {
    make_tactile_device(p);
    p.refuse_unknown();
  });
  EXPECT_NE(msg.find("'rise_time' is not a parameter of tactile (did you mean rise_time_s?)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix: use one of: device, rows"), std::string::npos) << msg;
}

TEST(Params, OutOfRangeValuesAreRefusedWithTheRange) {
  Params p("ffd");
  p.set("rate_hz", "100000");
  const std::string msg = error_of([&] { p.declare(*node_table("enact-ffd")); });
  EXPECT_NE(msg.find("'rate_hz' is out of range, got '100000' (allowed: 1..44000)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix: write e.g. rate_hz=5000 (Hz)"), std::string::npos) << msg;
}

TEST(Params, ALiveOnlyParameterIsRefusedAtStartNamingParamSet) {
  Params p("sim");
  p.set("scene", "s.yaml");
  p.set("reposition", "true");  // a command: only while the graph runs
  const std::string msg = error_of([&] { p.declare(sim_table()); });
  EXPECT_NE(msg.find("enact param set sim.reposition"), std::string::npos) << msg;
}

TEST(Components, SimulatorNeedsAScene) {
  EXPECT_NE(error_of([] { sim_params(Params("sim")); }).find("'scene' is required"), std::string::npos);
}

TEST(Components, OnlyKnownDevices) {
  Params p("ffd");
  p.set("device", "falcon-usb");
  const std::string msg = error_of([&] { make_force_device(p); });
  EXPECT_NE(msg.find("must be one of simulated, falcon, dhd, hd, inverse3, got 'falcon-usb' (did you mean falcon?)"), std::string::npos) << msg;
}

// where the simulated device's end-effector is at its first read, for these ffd parameters
math::Vec3 start_of(const std::map<std::string, std::string>& given) {
  Params p("ffd");
  for (const auto& [name, value] : given) p.set(name, value);
  auto device = make_force_device(p);
  device->activate();
  devices::ForceSample s;
  device->read(0, s);
  device->deactivate();
  return s.position_m;
}

// the device starts where the scene's body is (a user's scene, started live, is explored
// from its own start), unless start_m says otherwise; without either, the device's default
TEST(Components, TheDeviceStartsWhereTheScenesBodyIsUnlessStartMIsGiven) {
  const std::string scene = test::source_path("launch/scenes/two_boxes.yaml");  // a user's scene: two boxes with a gap
  EXPECT_EQ(start_of({{"start_scene", scene}}), (math::Vec3{-0.012, 0.003, 0.0115}));
  EXPECT_EQ(start_of({{"start_scene", scene}, {"start_m", ""}}), (math::Vec3{-0.012, 0.003, 0.0115})) << "an empty start_m (a launch argument left empty) is not given";
  EXPECT_EQ(start_of({{"start_scene", scene}, {"start_m", "0.001,0.002,0.02"}}), (math::Vec3{0.001, 0.002, 0.02}));
  const math::Vec3 otherwise = start_of({});
  EXPECT_EQ(otherwise.x, 0.0);
  EXPECT_NEAR(otherwise.z, 0.0125, 1e-12);
}

// every node's --help lists each of its declared parameters, from the one table
TEST(NodeTables, HelpListsEveryDeclaredParameter) {
  for (const char* exec : {"enact-sim", "enact-ffd", "enact-tactile", "enact-rt", "enact-logger", "enact-foxglove"}) {
    const ParamTable* t = node_table(exec);
    ASSERT_NE(t, nullptr) << exec;
    const std::string help = help_lines(*t);
    for (const ParamSpec& s : *t) EXPECT_NE(help.find("  " + s.name), std::string::npos) << exec << ": " << s.name;
    // a name declared twice in one node would be read with the first's default
    for (std::size_t i = 0; i < t->size(); ++i) {
      for (std::size_t j = i + 1; j < t->size(); ++j) EXPECT_NE((*t)[i].name, (*t)[j].name) << exec;
    }
  }
}

TEST(NodeTables, UnitsComeFromTheNames) {
  EXPECT_EQ(unit_of("rate_hz"), "Hz");
  EXPECT_EQ(unit_of("stiffness_n_per_m"), "N/m");
  EXPECT_EQ(unit_of("damping_n_s_per_m"), "N s/m");
  EXPECT_EQ(unit_of("start_m"), "m");
  EXPECT_EQ(unit_of("reentry_speed_m_per_s"), "m/s") << "a speed is not a time";
  EXPECT_EQ(unit_of("max_force_step_n_per_ms"), "N/ms");
  EXPECT_EQ(unit_of("mass_kg"), "kg");
  EXPECT_EQ(unit_of("model"), "");
}

// each live number of the simulator is one declaration: its row of the simulator's table (the
// --help, launch files' checks, enact param list) and the planner's range check are the same
// range; outside it a change is refused naming the parameter, its range and unit
TEST(LiveNumbers, EachIsARowOfTheSimulatorsTableWithTheRangeThePlannerChecks) {
  sim::Simulator simulator;
  sim::SimParams p;
  p.scene = test::source_path("launch/scenes/bridge.yaml");
  simulator.configure(p);
  sim::ParamPlanner planner(simulator);
  ASSERT_GE(sim::live_numbers().size(), 5u);
  for (const sim::LiveNumber& n : sim::live_numbers()) {
    const ParamSpec* spec = find_spec(sim_table(), n.name);
    ASSERT_NE(spec, nullptr) << n.name;
    EXPECT_TRUE(spec->live) << n.name;
    EXPECT_EQ(spec->type, ParamType::number) << n.name;
    EXPECT_EQ(spec->min, n.min) << n.name;
    EXPECT_EQ(spec->max, n.max) << n.name;
    EXPECT_TRUE(spec->at_start) << n.name << ": given at start too (a launch file, a sweep)";
    const std::string unit = unit_of(n.name).empty() ? "" : " " + unit_of(n.name);
    const sim::ParamPlan below = planner.plan(n.name, {n.min - 1.0, std::nullopt, std::nullopt}, 1);
    EXPECT_FALSE(below.accepted) << n.name;
    EXPECT_NE(below.reason.find(std::string(n.name) + " must be a number "), std::string::npos) << below.reason;
    const std::string range = std::isfinite(n.max) ? "from " + config::number(n.min) + " to " + config::number(n.max) + unit : ">= " + config::number(n.min) + unit;
    EXPECT_NE(below.reason.find(range), std::string::npos) << below.reason;
    if (std::isfinite(n.max)) {
      const sim::ParamPlan above = planner.plan(n.name, {n.max * 2.0 + 1.0, std::nullopt, std::nullopt}, 2);
      EXPECT_FALSE(above.accepted) << n.name;
      EXPECT_NE(above.reason.find(range), std::string::npos) << above.reason;
    }
  }
}

}  // namespace
}  // namespace enact::graph
