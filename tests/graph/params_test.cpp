// Node parameters from the command line: typed, checked, typos refused with the fix.
#include <gtest/gtest.h>

#include "core/config/yaml.h"
#include "core/graph/components.h"
#include "core/graph/params.h"
#include "tests/support/refusal.h"

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
  EXPECT_EQ(a.params.number("rate_hz", 0.0), 44000.0);
  EXPECT_EQ(a.params.scoped("sim").text("scene", ""), "s.yaml");
}

TEST(NodeArgs, UnknownArgumentIsRefused) {
  const std::string msg = error_of([] { parse({"x", "--rate", "5"}); });
  EXPECT_NE(msg.find("--rate"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
}

TEST(Params, TypesAreChecked) {
  Params p("ffd");
  p.set("k", "abc");
  p.set("on", "maybe");
  p.set("v", "1,2");
  EXPECT_NE(error_of([&] { p.number("k", 0.0); }).find("'k'"), std::string::npos);
  EXPECT_NE(error_of([&] { p.flag("on", false); }).find("true or false"), std::string::npos);
  EXPECT_NE(error_of([&] { p.vec3("v", {}); }).find("x,y,z"), std::string::npos);
  p.set("v", "0.1,0,-2e-3");
  EXPECT_EQ(p.vec3("v", {}), (physics::Vec3{0.1, 0.0, -2e-3}));
}

TEST(Params, ATypoIsRefusedListingTheKnownNames) {
  Params p("tactile");
  p.set("rise_time", "0.02");  // should be rise_time_s
  const std::string msg = error_of([&] {
    make_tactile_device(p);
    p.refuse_unread(kTactileParams);
  });
  EXPECT_NE(msg.find("rise_time"), std::string::npos) << msg;
  EXPECT_NE(msg.find("rise_time_s"), std::string::npos) << msg;
}

TEST(Components, SimulatorNeedsAScene) {
  EXPECT_NE(error_of([] { sim_params(Params("sim")); }).find("scene"), std::string::npos);
}

TEST(Components, OnlySimulatedDevicesForNow) {
  Params p("ffd");
  p.set("device", "falcon-usb");
  EXPECT_NE(error_of([&] { make_force_device(p); }).find("device=simulated"), std::string::npos);
}

}  // namespace
}  // namespace enact::graph
