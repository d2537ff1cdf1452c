// The scene for Foxglove's 3D panel from a SceneState and the bridge scene file: boxes where
// the scene's boxes are, the grid's masses coloured by contact, the force as an arrow along it.
#include <cmath>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/config/yaml.h"
#include "core/foxglove/bridge.h"
#include "core/foxglove/scene.h"
#include "core/physics/scene.h"
#include "tests/support/test_util.h"

namespace enact::foxglove {
namespace {

// v rotated by the quaternion q
math::Vec3 rotate(const ::foxglove::Quaternion& q, const math::Vec3& v) {
  const math::Vec3 u{q.x(), q.y(), q.z()};
  const auto cross = [](const math::Vec3& a, const math::Vec3& b) { return math::Vec3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; };
  const math::Vec3 t = cross(u, v) * 2.0;
  return v + t * q.w() + cross(u, t);
}

TEST(FoxgloveScene, BoxesGridContactsAndForceArrow) {
  const physics::Model model = physics::load_scene(test::source_path("launch/scenes/bridge.yaml"));
  const SceneConverter converter(model);
  msgs::SceneState state;
  state.mutable_header()->set_stamp_ns(2'500'000'000);
  state.mutable_body_position()->set_x(0.01);
  state.mutable_body_position()->set_z(0.02);
  for (int i = 0; i < 16; ++i) state.add_in_contact(i == 3 || i == 7);
  state.mutable_resultant_force()->set_y(-2.0);
  ::foxglove::SceneUpdate update;
  converter.convert(state, update);

  ASSERT_EQ(update.entities_size(), 2);
  const auto& fixed = update.entities(0);
  const auto& body = update.entities(1);
  EXPECT_EQ(fixed.frame_id(), kSceneFrame);
  EXPECT_EQ(fixed.timestamp().seconds(), 2);
  EXPECT_EQ(fixed.timestamp().nanos(), 500'000'000);
  // one cube per box of the scene, one more for the floor; each where its box is
  ASSERT_EQ(fixed.cubes_size(), static_cast<int>(model.boxes.size()) + 1);
  for (std::size_t b = 0; b < model.boxes.size(); ++b) {
    EXPECT_NEAR(fixed.cubes(b).pose().position().x(), model.boxes[b].center_m.x, 1e-12);
    EXPECT_NEAR(fixed.cubes(b).size().z(), 2 * model.boxes[b].half_extents_m.z, 1e-12);
    // the box's own x axis, through the quaternion
    const math::Vec3 x = rotate(fixed.cubes(b).pose().orientation(), {1, 0, 0});
    EXPECT_NEAR(x.x, model.boxes[b].rotation.c0.x, 1e-9);
    EXPECT_NEAR(x.y, model.boxes[b].rotation.c0.y, 1e-9);
  }
  // the grid: 16 masses around the body, the two in contact red
  ASSERT_EQ(body.spheres_size(), 16);
  int red = 0;
  for (int i = 0; i < 16; ++i) {
    const bool is_red = body.spheres(i).color().r() > 0.8 && body.spheres(i).color().g() < 0.3;
    EXPECT_EQ(is_red, i == 3 || i == 7) << i;
    red += is_red;
  }
  EXPECT_EQ(red, 2);
  // the arrow starts at the body and points along the force (-y), its length scaled by |F|
  ASSERT_EQ(body.arrows_size(), 1);
  const auto& arrow = body.arrows(0);
  EXPECT_NEAR(arrow.pose().position().x(), 0.01, 1e-12);
  const math::Vec3 dir = rotate(arrow.pose().orientation(), {1, 0, 0});
  EXPECT_NEAR(dir.y, -1.0, 1e-9);
  EXPECT_NEAR(arrow.shaft_length() + arrow.head_length(), 2.0 * kArrowLength_m_per_n, 1e-12);
  // no force, no arrow
  state.clear_resultant_force();
  converter.convert(state, update);
  EXPECT_EQ(update.entities(1).arrows_size(), 0);
}

// a scene that reads a file beside it (the ridge's height map), as a graph keeps it: it loads
// with the file put back beside it, and without it the error names the file
TEST(FoxgloveScene, ASceneLoadsWithTheFilesKeptBesideIt) {
  msgs::GraphInfo info;
  auto* scene = info.add_files();
  scene->set_name("rt.sim.scene");
  scene->set_data(test::read_file(test::source_path("launch/scenes/ridge.yaml")));
  const auto alone = scene_of(info);
  ASSERT_TRUE(alone);
  try {
    converter_for(*alone);
    ADD_FAILURE() << "the ridge loaded without its height map";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("ridge_heights.png"), std::string::npos) << e.what();
  }
  auto* heights = info.add_files();
  heights->set_name("rt.sim.scene/ridge_heights.png");
  heights->set_data(test::read_file(test::source_path("launch/scenes/ridge_heights.png")));
  const auto named = scene_of(info);
  ASSERT_TRUE(named);
  EXPECT_EQ(named->sim, "sim");
  ASSERT_EQ(named->beside.size(), 1u);
  EXPECT_NO_THROW(converter_for(*named));
}

TEST(FoxgloveScene, Base64MatchesRfc4648Vectors) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\xff\x00", 2)), "/wA=");
}

// the shipped layout (docs/foxglove-layout.json): the 3D panel shows foxglove/scene in frame
// `scene` without that frame's axes over it (Foxglove's default axes are ~20 cm long and
// thick, the bridge 3 cm: they hid it)
TEST(FoxgloveScene, TheShippedLayoutShowsTheSceneWithoutTheFramesAxes) {
  const nlohmann::json layout = nlohmann::json::parse(test::read_file(test::source_path("docs/foxglove-layout.json")));
  int panels = 0;
  for (const auto& [id, config] : layout["configById"].items()) {
    if (!id.starts_with("3D!")) continue;
    ++panels;
    EXPECT_TRUE(config["topics"][kSceneTopic]["visible"].get<bool>()) << id;
    EXPECT_EQ(config["followTf"], "scene") << id;
    EXPECT_FALSE(config["transforms"]["frame:scene"]["visible"].get<bool>()) << id;
    EXPECT_LE(config["scene"]["transforms"]["axisScale"].get<double>(), 0.1) << id;
    EXPECT_FALSE(config["scene"]["transforms"]["showLabel"].get<bool>()) << id;
  }
  EXPECT_EQ(panels, 1);
}

}  // namespace
}  // namespace enact::foxglove
