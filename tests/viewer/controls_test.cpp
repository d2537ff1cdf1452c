// The experimenter's controls: requests checked against the stability analysis before they
// are sent, the pre-check following what the simulator applied and its loop rate, and the
// keyboard shortcuts.
#include "core/viewer/panels.h"

#include <gtest/gtest.h>

#include "tests/support/test_util.h"

namespace enact::viewer {
namespace {

sim::ParamValue number(double v) { return {v, std::nullopt, std::nullopt}; }
sim::ParamValue text(const std::string& v) { return {std::nullopt, v, std::nullopt}; }

Controls bridge_controls() { return Controls("sim", test::source_path("launch/scenes/bridge.yaml")); }

TEST(Controls, AnUnstableStiffnessIsNotSent) {
  Controls c = bridge_controls();
  EXPECT_FALSE(c.request("stiffness_n_per_m", number(1e6)));
  EXPECT_NE(c.status().find("not sent"), std::string::npos) << c.status();
  EXPECT_NE(c.status().find("Colgate & Schenkel"), std::string::npos) << c.status();
  EXPECT_FALSE(c.request("damping_n_s_per_m", number(-1.0)));
}

TEST(Controls, AStableStiffnessIsSentAndCountsOnceApplied) {
  Controls c = bridge_controls();
  const auto u = c.request("stiffness_n_per_m", number(3000.0));
  ASSERT_TRUE(u);
  EXPECT_EQ(u->name(), "sim.stiffness_n_per_m");
  EXPECT_EQ(u->number(), 3000.0);
  EXPECT_EQ(c.stiffness_n_per_m(), 6000.0);  // not before the simulator applied it
  c.sent(5, *u);
  c.answered({5, u->name(), true, "", true});
  EXPECT_EQ(c.stiffness_n_per_m(), 3000.0);
  // a refused one changes nothing, and says why
  const auto v = c.request("stiffness_n_per_m", number(2000.0));
  ASSERT_TRUE(v);
  c.sent(6, *v);
  c.answered({6, v->name(), false, "the simulator said no", true});
  EXPECT_EQ(c.stiffness_n_per_m(), 3000.0);
  EXPECT_NE(c.status().find("the simulator said no"), std::string::npos);
}

TEST(Controls, ThePreCheckFollowsTheLoopRate) {
  // at 5 kHz the bridge may not get stiffer than loaded; at 44 kHz it is passive up to
  // (6 - 0.34) / (17 x T/2) = 29 302 N/m
  Controls c = bridge_controls();
  EXPECT_FALSE(c.request("stiffness_n_per_m", number(20000.0)));
  c.set_rate(44000.0);
  EXPECT_TRUE(c.request("stiffness_n_per_m", number(20000.0)));
  EXPECT_FALSE(c.request("stiffness_n_per_m", number(30000.0)));
}

TEST(Controls, ModelsAndCommandsAreLeftToTheSimulator) {
  Controls c = bridge_controls();
  const auto u = c.request("model", text("my-model.yaml"));
  ASSERT_TRUE(u);
  EXPECT_EQ(u->text(), "my-model.yaml");
  const auto t = c.request("trial", text("stop"));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->name(), "sim.trial");
}

TEST(Controls, KeysMakeTheirRequests) {
  EXPECT_EQ(key_action('3'), KeyAction::cm3);
  EXPECT_EQ(key_action('+'), KeyAction::stiffer);
  EXPECT_EQ(key_action('['), KeyAction::threshold_down);
  EXPECT_FALSE(key_action('z'));
  Controls c = bridge_controls();
  ViewModel model;
  const auto cm3 = c.on_key(KeyAction::cm3, model);
  ASSERT_EQ(cm3.size(), 1u);
  EXPECT_EQ(cm3[0].text(), "CM3");
  // stiffer than loaded: refused by the pre-check; softer: x 1/1.25
  EXPECT_TRUE(c.on_key(KeyAction::stiffer, model).empty());
  const auto softer = c.on_key(KeyAction::softer, model);
  ASSERT_EQ(softer.size(), 1u);
  EXPECT_DOUBLE_EQ(softer[0].number(), 4800.0);
  const auto up = c.on_key(KeyAction::threshold_up, model);
  ASSERT_EQ(up.size(), 1u);
  EXPECT_DOUBLE_EQ(up[0].number(), 0.0005);
  // a running trial is stopped by the toggle
  const auto toggle = c.on_key(KeyAction::trial_toggle, model);
  ASSERT_EQ(toggle.size(), 1u);
  EXPECT_EQ(toggle[0].text(), "stop");
}

TEST(Controls, WithoutTheSceneRequestsGoUnchecked) {
  Controls c("sim", "no/such/scene.yaml");
  EXPECT_NE(c.status().find("no stability pre-check"), std::string::npos) << c.status();
  EXPECT_TRUE(c.request("stiffness_n_per_m", number(1e6)));
  EXPECT_TRUE(c.on_key(KeyAction::stiffer, ViewModel{}).empty());
}

}  // namespace
}  // namespace enact::viewer
