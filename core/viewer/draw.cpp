#include "core/viewer/draw.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/graph/messages.h"

namespace enact::viewer {
namespace {

constexpr float kTitleX = 8.0f, kTitleY = 3.0f;
// consecutive trail samples (60 Hz) farther apart along the path than this are a jump
constexpr double kTrailJump_m = 0.003;

ImVec2 im(const Pixel& p) { return {p.x, p.y}; }

// a colour between a and b, t in [0, 1]
ImU32 mix(ImU32 a, ImU32 b, float t) {
  const ImVec4 ca = ImGui::ColorConvertU32ToFloat4(a), cb = ImGui::ColorConvertU32ToFloat4(b);
  t = std::clamp(t, 0.0f, 1.0f);
  return ImGui::ColorConvertFloat4ToU32({ca.x + (cb.x - ca.x) * t, ca.y + (cb.y - ca.y) * t, ca.z + (cb.z - ca.z) * t, 1.0f});
}

void text(ImDrawList& dl, float x, float y, ImU32 colour, const char* s) { dl.AddText({x, y}, colour, s); }

// grid mass i of the latest scene: position (m), in contact, its contact force (N)
struct Mass {
  math::Vec3 at_m;
  bool touching = false;
  math::Vec3 force_n;
};

std::vector<Mass> masses(const SceneGeometry& g, const msgs::SceneState& s) {
  std::vector<Mass> out;
  const math::Vec3 body = graph::get(s.body_position());
  for (std::size_t i = 0; i < g.grid_offsets_m.size(); ++i) {
    Mass m{body + g.grid_offsets_m[i], false, {}};
    if (static_cast<int>(i) < s.in_contact_size()) m.touching = s.in_contact(static_cast<int>(i));
    if (static_cast<int>(i) < s.contact_force_size()) m.force_n = graph::get(s.contact_force(static_cast<int>(i)));
    out.push_back(m);
  }
  return out;
}

}  // namespace

float mass_radius(const SceneGeometry& g, const TopView& view) {
  // a third of the grid pitch, at least 2 px
  const double pitch = g.grid_offsets_m.size() > 1 ? math::norm(g.grid_offsets_m[1] - g.grid_offsets_m[0]) : 0.0025;
  return std::max(2.0f, static_cast<float>(pitch / 3.0) * view.pixels_per_m());
}

void draw_panel(ImDrawList& dl, const Rect& r, const char* title) {
  dl.AddRectFilled({r.x0, r.y0}, {r.x1, r.y1}, palette::kPanel);
  dl.AddRect({r.x0, r.y0}, {r.x1, r.y1}, palette::kBackground, 0.0f, 0, 2.0f);
  text(dl, r.x0 + kTitleX, r.y0 + kTitleY, palette::kTitle, title);
}

void draw_top_view(ImDrawList& dl, const Rect& r, const SceneGeometry& g, const ViewModel& model) {
  draw_panel(dl, r, "top view (x right, y forward)");
  if (g.faces.empty() && g.rounds.empty() && !g.has_path) text(dl, r.x0 + kTitleX, r.y0 + 24, palette::kTitle, "no scene yet (it comes with the graph, or give --scene)");
  const TopView view(g, r);
  // the workspace, the boxes seen from above, the task path's centreline
  dl.AddRect(im(view.to_screen(g.view_min_m.x_m, g.view_max_m.y_m)), im(view.to_screen(g.view_max_m.x_m, g.view_min_m.y_m)), palette::kWorkspace);
  for (const TopFace& f : g.faces) {
    ImVec2 quad[4];
    for (int i = 0; i < 4; ++i) quad[i] = im(view.to_screen(f.corner[i].x_m, f.corner[i].y_m));
    dl.AddConvexPolyFilled(quad, 4, f.task_surface ? palette::kBridge : palette::kOtherBox);
  }
  // spheres and capsules: a disc at each end of the axis, the band between them
  for (const RoundTop& round : g.rounds) {
    const ImU32 colour = round.task_surface ? palette::kBridge : palette::kOtherBox;
    const float radius = static_cast<float>(round.radius_m) * view.pixels_per_m();
    const ImVec2 a = im(view.to_screen(round.from.x_m, round.from.y_m)), b = im(view.to_screen(round.to.x_m, round.to.y_m));
    dl.AddCircleFilled(a, radius, colour, 32);
    dl.AddCircleFilled(b, radius, colour, 32);
    const float dx = b.x - a.x, dy = b.y - a.y, length = std::sqrt(dx * dx + dy * dy);
    if (length > 0.5f) {
      const float nx = -dy / length * radius, ny = dx / length * radius;
      const ImVec2 band[4] = {{a.x + nx, a.y + ny}, {b.x + nx, b.y + ny}, {b.x - nx, b.y - ny}, {a.x - nx, a.y - ny}};
      dl.AddConvexPolyFilled(band, 4, colour);
    }
  }
  if (g.has_path) {
    const auto& pts = g.path.points();
    for (std::size_t i = 1; i < pts.size(); ++i) {
      dl.AddLine(im(view.to_screen(pts[i - 1].x_m, pts[i - 1].y_m)), im(view.to_screen(pts[i].x_m, pts[i].y_m)), palette::kCentreline, 1.0f);
    }
  }
  // the trail of the body centre
  const auto& trail = model.trail();
  for (std::size_t i = 1; i < trail.size(); ++i) {
    dl.AddLine(im(view.to_screen(trail[i - 1].x, trail[i - 1].y)), im(view.to_screen(trail[i].x, trail[i].y)), palette::kTrail, 2.0f);
  }
  if (!model.has_scene()) {
    text(dl, r.x0 + kTitleX, r.y1 - 20, palette::kTitle, "no sim/scene yet");
    return;
  }
  // the grid, masses in contact highlighted
  const float radius = mass_radius(g, view);
  for (const Mass& m : masses(g, model.scene())) {
    dl.AddCircleFilled(im(view.to_screen(m.at_m.x, m.at_m.y)), radius, m.touching ? palette::kMassContact : palette::kMassFree, 12);
  }
  char line[96];
  const math::Vec3 body = graph::get(model.scene().body_position());
  std::snprintf(line, sizeof line, "body (%.2f, %.2f, %.2f) mm", body.x * 1e3, body.y * 1e3, body.z * 1e3);
  text(dl, r.x0 + kTitleX, r.y1 - 20, palette::kTitle, line);
}

void draw_side_view(ImDrawList& dl, const Rect& r, const SceneGeometry& g, const ViewModel& model) {
  draw_panel(dl, r, "side view: height vs the top surface (mm) along the path (mm), per-mass force");
  if (!g.has_path) {
    text(dl, r.x0 + kTitleX, r.y0 + 24, palette::kTitle, "the scene has no task path");
    return;
  }
  const SideView view(g, r);
  const double length = g.path.length_m();
  // the bridge under its top surface; see-through where the body is beside it (in front of
  // or behind it in this projection, never inside it)
  const bool body_beside = model.has_scene() && beside_path(g, model.scene().body_position().x(), model.scene().body_position().y());
  dl.AddRectFilled(im(view.to_screen(0.0, g.top_z_m)), im(view.to_screen(length, g.top_z_m - SideView::kBelow_m)), body_beside ? palette::kBridgeBehind : palette::kBridge);
  // height marks above and below the top, and the distance along the path
  for (const AxisMark& m : axis_marks(-SideView::kBelow_m * 1e3, SideView::kAbove_m * 1e3, 6, "mm")) {
    text(dl, r.x0 + 2, view.to_screen(0.0, g.top_z_m + m.value * 1e-3).y - 7, palette::kWorkspace, m.label.c_str());
  }
  const auto along = axis_marks(0.0, std::floor(length * 1e2) * 10.0, 4, "mm");
  for (std::size_t i = 1; i < along.size(); ++i) {
    const Pixel p = view.to_screen(along[i].value * 1e-3, g.top_z_m - SideView::kBelow_m);
    const float w = ImGui::CalcTextSize(along[i].label.c_str()).x;
    dl.AddLine({p.x, p.y}, {p.x, p.y - 4}, palette::kTitle);
    text(dl, std::min(p.x - w / 2, r.x1 - w - 4), p.y - 18, palette::kTitle, along[i].label.c_str());
  }
  // the trail: height of the body centre against the distance along the path (off the
  // path, the closest point may jump to another segment: no line across such a jump);
  // beside the bridge in its own colour
  const auto& trail = model.trail();
  for (std::size_t i = 1; i < trail.size(); ++i) {
    const auto a = g.path.project(trail[i - 1].x, trail[i - 1].y), b = g.path.project(trail[i].x, trail[i].y);
    if (std::abs(b.arc_length_m - a.arc_length_m) > kTrailJump_m) continue;
    const ImU32 colour = beside_path(g, trail[i].x, trail[i].y) ? palette::kBeside : palette::kTrail;
    dl.AddLine(im(view.to_screen(a.arc_length_m, trail[i - 1].z)), im(view.to_screen(b.arc_length_m, trail[i].z)), colour, 2.0f);
  }
  if (!model.has_scene()) return;
  // the grid masses and their contact force, 100 px per N upwards; beside the bridge: rings
  for (const Mass& m : masses(g, model.scene())) {
    const Pixel p = view.to_screen(g.path.project(m.at_m.x, m.at_m.y).arc_length_m, m.at_m.z);
    dl.AddLine(im(p), {p.x, p.y - std::min(100.0f * static_cast<float>(m.force_n.z), r.height())}, palette::kForce, 2.0f);
    if (beside_path(g, m.at_m.x, m.at_m.y)) dl.AddCircle(im(p), 3.5f, palette::kBeside, 8, 1.5f);
    else dl.AddCircleFilled(im(p), 3.0f, m.touching ? palette::kMassContact : palette::kMassFree, 8);
  }
  if (body_beside) {
    const auto side = g.path.project(model.scene().body_position().x(), model.scene().body_position().y());
    char line[96];
    std::snprintf(line, sizeof line, "body beside the bridge, %.1f mm off its edge", (std::abs(side.lateral_m) - g.path_width_m / 2) * 1e3);
    text(dl, r.x1 - 300, r.y0 + kTitleY + 16, palette::kBeside, line);
  }
}

void draw_plot(ImDrawList& dl, const Rect& r, const std::vector<float>& values, std::size_t slots, double y_max, const char* unit, const char* title, double span_s) {
  // the plot area: room for the y marks on the left, the time marks below, the title above
  constexpr float kLeft = 52.0f, kBelow = 16.0f, kAbove = 18.0f;
  const Rect area{r.x0 + kLeft, r.y0 + kAbove, r.x1 - 8.0f, r.y1 - kBelow};
  text(dl, r.x0 + 4, r.y0 + 1, palette::kTitle, title);
  dl.AddRect({area.x0, area.y0}, {area.x1, area.y1}, palette::kWorkspace);
  auto y_of = [&](double v) { return area.y1 - static_cast<float>(std::clamp(v / y_max, 0.0, 1.0)) * area.height(); };
  for (const AxisMark& m : axis_marks(0.0, y_max, 2, unit)) {
    const float y = y_of(m.value);
    dl.AddLine({area.x0 - 3, y}, {area.x1, y}, palette::kWorkspace);
    text(dl, r.x0 + 2, y - 7, palette::kTitle, m.label.c_str());
  }
  for (const AxisMark& m : axis_marks(-span_s, 0.0, 2, "s")) {
    const float x = area.x0 + static_cast<float>((m.value + span_s) / span_s) * area.width();
    dl.AddLine({x, area.y1}, {x, area.y1 + 3}, palette::kWorkspace);
    text(dl, std::min(x - 12, area.x1 - 28), area.y1 + 2, palette::kTitle, m.label.c_str());
  }
  // the values, the newest at the right edge
  const std::size_t n = values.size();
  const float dx = area.width() / static_cast<float>(std::max<std::size_t>(slots, 2) - 1);
  auto x_of = [&](std::size_t i) { return area.x1 - static_cast<float>(n - 1 - i) * dx; };
  for (std::size_t i = 1; i < n; ++i) dl.AddLine({x_of(i - 1), y_of(values[i - 1])}, {x_of(i), y_of(values[i])}, palette::kTrail, 1.5f);
}

void draw_pins(ImDrawList& dl, const Rect& r, const ViewModel& model) {
  // as the cells show them (tactile/shown); before that, as the model asks (sim/scene)
  std::vector<float> levels = model.shown();
  int rows = model.shown_rows(), cols = model.shown_cols();
  const bool shown = !levels.empty();
  if (!shown && model.has_scene()) {
    levels.assign(model.scene().pin_level().begin(), model.scene().pin_level().end());
    rows = cols = static_cast<int>(std::lround(std::sqrt(static_cast<double>(levels.size()))));
  }
  draw_panel(dl, r, shown ? "pins as shown (tactile/shown)" : "pins as asked (sim/scene)");
  if (rows <= 0 || cols <= 0 || static_cast<int>(levels.size()) < rows * cols) return;
  const float cell = std::min((r.width() - 24) / static_cast<float>(cols), (r.height() - 36) / static_cast<float>(rows));
  const float x0 = r.x0 + (r.width() - cell * static_cast<float>(cols)) / 2, y0 = r.y0 + 26;
  for (int row = 0; row < rows; ++row) {
    for (int col = 0; col < cols; ++col) {
      const ImVec2 c{x0 + (static_cast<float>(col) + 0.5f) * cell, y0 + (static_cast<float>(row) + 0.5f) * cell};
      dl.AddCircleFilled(c, cell * 0.35f, mix(palette::kPinDown, palette::kPinUp, levels[row * cols + col]), 20);
      dl.AddCircle(c, cell * 0.35f, palette::kWorkspace, 20);
    }
  }
}

void draw_forces(ImDrawList& dl, const Rect& r, const SceneGeometry& g, const ViewModel& model) {
  draw_panel(dl, r, "forces: per mass |F| (grid) and the resultant");
  if (!model.has_scene() || g.cols <= 0) return;
  const std::vector<Mass> ms = masses(g, model.scene());
  double largest = 0.1;
  for (const Mass& m : ms) largest = std::max(largest, math::norm(m.force_n));
  // one cell per grid mass, filled in proportion to its force
  const float cell = std::min((r.width() - 24) / static_cast<float>(g.cols), (r.height() - 64) / static_cast<float>(g.rows));
  const float x0 = r.x0 + 12, y0 = r.y0 + 24;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const float cx = x0 + static_cast<float>(static_cast<int>(i) % g.cols) * cell, cy = y0 + static_cast<float>(static_cast<int>(i) / g.cols) * cell;
    const float fill = static_cast<float>(math::norm(ms[i].force_n) / largest);
    dl.AddRect({cx + 2, cy + 2}, {cx + cell - 2, cy + cell - 2}, palette::kWorkspace);
    dl.AddRectFilled({cx + 3, cy + cell - 3 - (cell - 6) * fill}, {cx + cell - 3, cy + cell - 3}, ms[i].touching ? palette::kMassContact : palette::kForce);
  }
  const math::Vec3 f = graph::get(model.scene().resultant_force());
  char line[128];
  std::snprintf(line, sizeof line, "resultant (%.3f, %.3f, %.3f) N, |F| %.3f N", f.x, f.y, f.z, math::norm(f));
  text(dl, r.x0 + kTitleX, r.y1 - 36, palette::kTitle, line);
  std::snprintf(line, sizeof line, "full cell = %.3f N (largest mass force)", largest);
  text(dl, r.x0 + kTitleX, r.y1 - 20, palette::kWorkspace, line);
}

}  // namespace enact::viewer
