// Where the viewer draws: the layout, the scene-to-pixel mappings, and what the top view
// puts into an ImGui draw list (run headless: an ImGui context without any window).
#include "core/viewer/draw.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/physics/scene.h"
#include "core/viewer/layout.h"
#include "core/viewer/scene_geometry.h"
#include "tests/support/test_util.h"

namespace enact::viewer {
namespace {

float area(const Rect& r) { return r.width() * r.height(); }
float overlap(const Rect& a, const Rect& b) {
  const float w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0), h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
  return w > 0 && h > 0 ? w * h : 0.0f;
}

SceneGeometry bridge() { return load_geometry(test::source_path("launch/scenes/bridge.yaml")); }

TEST(Layout, PanelsTileTheWindowWithoutOverlapping) {
  for (const auto& [w, h] : std::vector<std::pair<float, float>>{{1280, 800}, {1920, 1080}, {640, 480}}) {
    const Layout l = layout(w, h);
    const std::vector<Rect> panels{l.top_view, l.side_view, l.pins, l.forces, l.plot, l.task, l.controls, l.status};
    float total = 0;
    for (std::size_t i = 0; i < panels.size(); ++i) {
      total += area(panels[i]);
      for (std::size_t j = i + 1; j < panels.size(); ++j) EXPECT_EQ(overlap(panels[i], panels[j]), 0.0f) << i << " and " << j;
    }
    EXPECT_NEAR(total, w * h, 1.0f);
  }
}

TEST(Layout, TopViewFitsTheWorkspaceWithOneScaleAndYUp) {
  const SceneGeometry g = bridge();
  // the ERGOS workspace, 60 x 60 mm
  EXPECT_DOUBLE_EQ(g.view_min_m.x_m, -0.030);
  EXPECT_DOUBLE_EQ(g.view_max_m.y_m, 0.030);
  const Rect r = layout(1280, 800).top_view;
  const TopView v(g, r);
  const Pixel lo = v.to_screen(-0.030, -0.030), hi = v.to_screen(0.030, 0.030);
  EXPECT_TRUE(r.contains(lo.x, lo.y) && r.contains(hi.x, hi.y));
  EXPECT_LT(hi.y, lo.y);  // forward is up
  EXPECT_NEAR(hi.x - lo.x, lo.y - hi.y, 1e-3);
  EXPECT_NEAR(hi.x - lo.x, 0.060f * v.pixels_per_m(), 1e-3);
  // the fitted area fills the panel's shorter side but for the margins
  EXPECT_GT(hi.x - lo.x, 0.85f * std::min(r.width(), r.height()));
}

TEST(Layout, SideViewPutsTheTopSurfaceAtItsHeight) {
  const SceneGeometry g = bridge();
  const Rect r = layout(1280, 800).side_view;
  const SideView v(g, r);
  const Pixel start = v.to_screen(0.0, g.top_z_m), end = v.to_screen(g.path.length_m(), g.top_z_m);
  const Pixel below = v.to_screen(0.0, g.top_z_m - SideView::kBelow_m), above = v.to_screen(0.0, g.top_z_m + SideView::kAbove_m);
  EXPECT_NEAR(start.y, end.y, 1e-3);
  EXPECT_NEAR((below.y - start.y) / (below.y - above.y), SideView::kBelow_m / (SideView::kBelow_m + SideView::kAbove_m), 1e-5);
  EXPECT_TRUE(r.contains(start.x, below.y - 1) && r.contains(end.x - 1, above.y));
}

TEST(SceneGeometry, TheBridgeIsThreeTopFacesAlongItsPath) {
  const SceneGeometry g = bridge();
  ASSERT_TRUE(g.has_path);
  ASSERT_EQ(g.faces.size(), 3u);
  for (const TopFace& f : g.faces) {
    EXPECT_TRUE(f.task_surface);
    EXPECT_NEAR(f.top_z_m, 0.012, 1e-12);
  }
  EXPECT_NEAR(g.path.length_m(), 0.063, 1e-4);  // three segments of 21 mm
  EXPECT_EQ(g.rows * g.cols, 16);
  EXPECT_NEAR(g.grid_offsets_m[0].x, -1.5 * 0.00245, 1e-12);  // row 0 col 0: far left
  EXPECT_NEAR(g.grid_offsets_m[0].y, 1.5 * 0.00245, 1e-12);
}

// a scene of meshes: the upward triangles of the height map (2 a cell) and of the wedge (its
// slope) seen from above, each with the corners of a mesh triangle
TEST(SceneGeometry, MeshesAreTheirUpwardTrianglesSeenFromAbove) {
  const physics::Model m = physics::load_scene(test::source_path("launch/scenes/shapes.yaml"));
  const SceneGeometry g = geometry_of(m);
  ASSERT_EQ(g.faces.size(), 2u * 8u * 8u + 2u);
  const physics::Mesh& wedge = m.meshes[m.objects[m.find_object("wedge")].mesh];
  const TopFace& slope = g.faces.back();
  EXPECT_NEAR(slope.top_z_m, 0.005, 1e-12);  // the wedge's high edge
  for (const task::Point2& c : slope.corner) {
    const bool a_vertex = std::any_of(wedge.vertices_m.begin(), wedge.vertices_m.end(),
                                      [&](const math::Vec3& v) { return std::abs(v.x - c.x_m) < 1e-12 && std::abs(v.y - c.y_m) < 1e-12; });
    EXPECT_TRUE(a_vertex) << c.x_m << ", " << c.y_m;
  }
}

// spheres and capsules seen from above: a disc, or two joined by a band; the view holds them
TEST(SceneGeometry, SpheresAndCapsulesAreDiscsSeenFromAbove) {
  const SceneGeometry g = load_geometry(test::source_path("launch/scenes/shapes.yaml"));
  ASSERT_EQ(g.rounds.size(), 2u);
  const RoundTop& ball = g.rounds[0];
  EXPECT_NEAR(ball.from.x_m, -0.013, 1e-12);
  EXPECT_NEAR(ball.to.y_m, -0.013, 1e-12);
  EXPECT_NEAR(ball.radius_m, 0.007, 1e-12);
  EXPECT_NEAR(ball.top_z_m, 0.014, 1e-12);
  const RoundTop& rod = g.rounds[1];
  EXPECT_NEAR(rod.to.x_m - rod.from.x_m, 0.016, 1e-12);
  EXPECT_NEAR(rod.radius_m, 0.004, 1e-12);
  EXPECT_EQ(g.task_surface, "");
  EXPECT_EQ(bridge().task_surface, "bridge");
  EXPECT_EQ(load_geometry(test::source_path("launch/scenes/ridge.yaml")).task_surface, "ridge");
}

// an ImGui frame with no window and no renderer: enough to fill draw lists
class Headless : public ::testing::Test {
 protected:
  void SetUp() override {
    context_ = ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = {1280, 800};
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    ImGui::NewFrame();
  }
  void TearDown() override {
    ImGui::EndFrame();
    ImGui::DestroyContext(context_);
  }

  // the draw list's vertices of one colour within `radius` px of `at`
  static std::vector<ImVec2> vertices(const ImDrawList& dl, ImU32 colour, Pixel at, float radius) {
    std::vector<ImVec2> out;
    for (const ImDrawVert& v : dl.VtxBuffer) {
      if (v.col == colour && std::hypot(v.pos.x - at.x, v.pos.y - at.y) <= radius) out.push_back(v.pos);
    }
    return out;
  }

  ImGuiContext* context_ = nullptr;
};

TEST_F(Headless, TopViewDrawsTheBridgeFacesAndTheGridWhereTheSceneSays) {
  const SceneGeometry g = bridge();
  const physics::Model model = physics::load_scene(test::source_path("launch/scenes/bridge.yaml"));
  // a scene: the body over the start of the path, its first 6 masses in contact
  msgs::SceneState s;
  const math::Vec3 body{-0.0074246, -0.0222739, 0.0119};
  s.mutable_body_position()->set_x(body.x);
  s.mutable_body_position()->set_y(body.y);
  s.mutable_body_position()->set_z(body.z);
  for (int i = 0; i < 16; ++i) {
    s.add_in_contact(i < 6);
    s.add_contact_force();
  }
  ViewModel vm;
  vm.on_scene(s);
  const Rect r = layout(1280, 800).top_view;
  ImDrawList& dl = *ImGui::GetBackgroundDrawList();
  draw_top_view(dl, r, g, vm);
  const TopView view(g, r);
  // each box of the bridge (from the scene file, independently of the viewer's geometry):
  // its top face's corners are vertices of the bridge colour (anti-aliasing moves them by
  // half a pixel)
  const physics::Object& bridge_object = model.objects[model.find_object("bridge")];
  ASSERT_EQ(bridge_object.box_count, 3);
  for (int b = bridge_object.first_box; b < bridge_object.first_box + bridge_object.box_count; ++b) {
    const physics::Box& box = model.boxes[b];
    for (const double sx : {-1.0, 1.0}) {
      for (const double sy : {-1.0, 1.0}) {
        const math::Vec3 c = box.center_m + box.rotation * math::Vec3{sx * box.half_extents_m.x, sy * box.half_extents_m.y, box.half_extents_m.z};
        EXPECT_FALSE(vertices(dl, palette::kBridge, view.to_screen(c.x, c.y), 1.0f).empty()) << "box " << b << " corner " << sx << ", " << sy;
      }
    }
  }
  // each grid mass: a disc of its colour centred where the body puts it
  const float radius = mass_radius(g, view);
  for (int i = 0; i < 16; ++i) {
    const physics::Point& p = model.points[model.proxies[0].first_body + i];
    const Pixel at = view.to_screen(body.x + p.offset_m.x, body.y + p.offset_m.y);
    const std::vector<ImVec2> disc = vertices(dl, i < 6 ? palette::kMassContact : palette::kMassFree, at, radius + 1.0f);
    ASSERT_GE(disc.size(), 8u) << "mass " << i;
    ImVec2 mean{0, 0};
    for (const ImVec2& v : disc) mean = {mean.x + v.x / static_cast<float>(disc.size()), mean.y + v.y / static_cast<float>(disc.size())};
    EXPECT_NEAR(mean.x, at.x, 0.5f) << "mass " << i;
    EXPECT_NEAR(mean.y, at.y, 0.5f) << "mass " << i;
  }
}

// the ball of the shapes scene: a disc of its radius, centred on it
TEST_F(Headless, TopViewDrawsASphereAsADisc) {
  const SceneGeometry g = load_geometry(test::source_path("launch/scenes/shapes.yaml"));
  ViewModel vm;
  const Rect r = layout(1280, 800).top_view;
  ImDrawList& dl = *ImGui::GetBackgroundDrawList();
  draw_top_view(dl, r, g, vm);
  const TopView view(g, r);
  const Pixel centre = view.to_screen(-0.013, -0.013);
  const float radius = 0.007f * view.pixels_per_m();
  // its rim: vertices of the box colour at the radius all round (anti-aliasing: within a pixel)
  int rim = 0;
  for (const ImDrawVert& v : dl.VtxBuffer) {
    rim += v.col == palette::kOtherBox && std::abs(std::hypot(v.pos.x - centre.x, v.pos.y - centre.y) - radius) < 1.0f;
  }
  EXPECT_GE(rim, 32) << "the disc's 32 segments";
}

TEST_F(Headless, WithoutASceneThereIsNoGrid) {
  const SceneGeometry g = bridge();
  ViewModel vm;
  ImDrawList& dl = *ImGui::GetBackgroundDrawList();
  draw_top_view(dl, layout(1280, 800).top_view, g, vm);
  for (const ImDrawVert& v : dl.VtxBuffer) {
    EXPECT_NE(v.col, palette::kMassFree);
    EXPECT_NE(v.col, palette::kMassContact);
  }
}

// the scene of a body at (x, y), 6 mm below the bridge's top (fallen), no contact
ViewModel body_at(double x_m, double y_m, double z_m) {
  msgs::SceneState s;
  s.mutable_body_position()->set_x(x_m);
  s.mutable_body_position()->set_y(y_m);
  s.mutable_body_position()->set_z(z_m);
  for (int i = 0; i < 16; ++i) s.add_in_contact(false), s.add_contact_force();
  ViewModel vm;
  vm.on_scene(s);
  return vm;
}

// how many vertices of `dl` have `colour`
long count_colour(const ImDrawList& dl, ImU32 colour) {
  return std::count_if(dl.VtxBuffer.begin(), dl.VtxBuffer.end(), [&](const ImDrawVert& v) { return v.col == colour; });
}

TEST_F(Headless, SideViewDrawsABodyBesideTheBridgeAsBesideIt) {
  const SceneGeometry g = bridge();
  const Rect r = layout(1280, 800).side_view;
  // beside the bridge (off the edge of its first segment), fallen below its top: rings of
  // the beside colour, the bridge see-through behind, no mass drawn as a solid disc in it
  const double half_width = g.path_width_m / 2;
  const task::Point2 corner = g.path.at(g.path.length_m() / 6);
  const auto side = g.path.project(corner.x_m + 3 * half_width, corner.y_m);
  ASSERT_GT(std::abs(side.lateral_m), half_width) << "the test's point must be beside the path";
  EXPECT_TRUE(beside_path(g, corner.x_m + 3 * half_width, corner.y_m));
  ImDrawList& dl = *ImGui::GetBackgroundDrawList();
  draw_side_view(dl, r, g, body_at(corner.x_m + 3 * half_width, corner.y_m, g.top_z_m - 0.006));
  EXPECT_GT(count_colour(dl, palette::kBeside), 16 * 8);
  EXPECT_GT(count_colour(dl, palette::kBridgeBehind), 0);
  EXPECT_EQ(count_colour(dl, palette::kBridge), 0);
  EXPECT_EQ(count_colour(dl, palette::kMassFree), 0);
  // on the bridge's centreline, just above it: an opaque bridge, solid discs but for the
  // grid's two corners that overhang the 10 mm wide bridge on a 45 degree segment (they are
  // 5.2 mm from the centreline)
  ImDrawList& on = *ImGui::GetForegroundDrawList();
  EXPECT_FALSE(beside_path(g, corner.x_m, corner.y_m));
  draw_side_view(on, r, g, body_at(corner.x_m, corner.y_m, g.top_z_m + 0.001));
  EXPECT_GT(count_colour(on, palette::kBridge), 0);
  EXPECT_EQ(count_colour(on, palette::kBridgeBehind), 0);
  EXPECT_EQ(count_colour(on, palette::kMassFree), 14 * 8);
}

TEST(Layout, PlotAxesCarryTheirUnits) {
  std::vector<std::string> labels;
  for (const AxisMark& m : axis_marks(0.0, 5.0, 2, "N")) labels.push_back(m.label);
  EXPECT_EQ(labels, (std::vector<std::string>{"0 N", "2.5 N", "5 N"}));
  labels.clear();
  for (const AxisMark& m : axis_marks(-10.0, 0.0, 2, "s")) labels.push_back(m.label);
  EXPECT_EQ(labels, (std::vector<std::string>{"-10 s", "-5 s", "0 s"}));
  EXPECT_DOUBLE_EQ(axis_marks(-8.0, 4.0, 6, "mm")[4].value, 0.0);
  EXPECT_EQ(axis_marks(-8.0, 4.0, 6, "mm")[4].label, "0 mm");
}

TEST(Layout, PlotScalesAreRoundAndAboveThePeak) {
  EXPECT_DOUBLE_EQ(round_scale(0.0, 0.1), 0.1);
  EXPECT_DOUBLE_EQ(round_scale(0.13, 0.1), 0.2);
  EXPECT_DOUBLE_EQ(round_scale(1.0, 0.1), 1.0);
  EXPECT_DOUBLE_EQ(round_scale(2.4, 0.1), 5.0);
  EXPECT_DOUBLE_EQ(round_scale(7.0, 0.1), 10.0);
  EXPECT_DOUBLE_EQ(round_scale(31.0, 0.1), 50.0);
}

}  // namespace
}  // namespace enact::viewer
