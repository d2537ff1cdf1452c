#include "core/viewer/layout.h"

#include <cmath>
#include <cstdio>

#include <algorithm>

namespace enact::viewer {
namespace {

// inside a panel, around what is drawn; room for a title line at the top
constexpr float kPad = 12.0f;
constexpr float kTitle = 18.0f;

}  // namespace

Layout layout(float w, float h) {
  // columns: the scene 7/16 of the width, then two of 9/32; rows in tenths of the height
  const float left = w * 7.0f / 16.0f, mid = left + w * 9.0f / 32.0f;
  Layout l;
  l.top_view = {0, 0, left, h * 0.70f};
  l.side_view = {0, h * 0.70f, left, h};
  l.pins = {left, 0, mid, h * 0.25f};
  l.forces = {left, h * 0.25f, mid, h * 0.50f};
  l.plot = {left, h * 0.50f, mid, h * 0.75f};
  l.task = {mid, 0, w, h * 0.225f};
  l.controls = {mid, h * 0.225f, w, h * 0.75f};
  l.status = {left, h * 0.75f, w, h};
  return l;
}

TopView::TopView(const SceneGeometry& g, const Rect& r) {
  const double dx = std::max(g.view_max_m.x_m - g.view_min_m.x_m, 1e-6), dy = std::max(g.view_max_m.y_m - g.view_min_m.y_m, 1e-6);
  const float w = r.width() - 2 * kPad, h = r.height() - 2 * kPad - kTitle;
  scale_ = static_cast<float>(std::min(w / dx, h / dy));
  // centred in the free area
  ox_ = r.x0 + kPad + (w - static_cast<float>(dx) * scale_) / 2;
  oy_ = r.y1 - kPad - (h - static_cast<float>(dy) * scale_) / 2;
  x0_m_ = g.view_min_m.x_m;
  y0_m_ = g.view_min_m.y_m;
}

Pixel TopView::to_screen(double x_m, double y_m) const {
  return {ox_ + static_cast<float>(x_m - x0_m_) * scale_, oy_ - static_cast<float>(y_m - y0_m_) * scale_};
}

SideView::SideView(const SceneGeometry& g, const Rect& r)
    : plot_{r.x0 + kPad, r.y0 + kPad + kTitle, r.x1 - kPad, r.y1 - kPad},
      length_m_(std::max(g.path.length_m(), 1e-6)),
      z0_m_(g.top_z_m - kBelow_m),
      z1_m_(g.top_z_m + kAbove_m),
      sx_(plot_.width() / static_cast<float>(length_m_)) {}

Pixel SideView::to_screen(double along_m, double z_m) const {
  const float fz = static_cast<float>((z_m - z0_m_) / (z1_m_ - z0_m_));
  return {plot_.x0 + static_cast<float>(along_m) * sx_, plot_.y1 - fz * plot_.height()};
}

std::vector<AxisMark> axis_marks(double from, double to, int divisions, const std::string& unit) {
  std::vector<AxisMark> marks;
  for (int i = 0; i <= divisions; ++i) {
    const double v = from + (to - from) * i / divisions;
    char label[32];
    std::snprintf(label, sizeof label, "%g %s", std::abs(v) < 1e-12 ? 0.0 : v, unit.c_str());
    marks.push_back({v, label});
  }
  return marks;
}

bool beside_path(const SceneGeometry& g, double x_m, double y_m) {
  return g.has_path && std::abs(g.path.project(x_m, y_m).lateral_m) > g.path_width_m / 2;
}

double round_scale(double value, double floor) {
  if (!(value > floor)) return floor;
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (const double step : {1.0, 2.0, 5.0}) {
    if (step * decade >= value) return step * decade;
  }
  return 10.0 * decade;
}

}  // namespace enact::viewer
