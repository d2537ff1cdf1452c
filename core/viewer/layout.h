#pragma once
// Where the viewer draws what, in window pixels (origin top-left, y down), for any window
// size, and the mappings from scene coordinates (m) to those pixels. Tests use the same
// functions to find the bridge and the grid in a snapshot.
#include <string>
#include <vector>

#include "core/task/polyline.h"
#include "core/viewer/scene_geometry.h"

namespace enact::viewer {

struct Rect {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  float width() const { return x1 - x0; }
  float height() const { return y1 - y0; }
  bool contains(float x, float y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

struct Pixel {
  float x = 0, y = 0;
};

// the panels: left the scene (top view over side view), middle the pins, the forces and the
// plot, right the task and the experimenter's controls, bottom right every node's status
struct Layout {
  Rect top_view, side_view, pins, forces, plot, task, controls, status;
};
Layout layout(float width, float height);

// a plot's round upper bound: the smallest 1, 2 or 5 x 10^k at or above `value` (`floor`
// when value is not above it), so the scale printed with the plot reads at a glance
double round_scale(double value, double floor);

// a labelled mark of a plot axis: where (in the axis' unit) and its text with the unit
struct AxisMark {
  double value = 0.0;
  std::string label;
};
// `divisions` + 1 marks evenly from `from` to `to`, each labelled with `unit` ("2.5 N",
// "-10 s"), the shortest text that tells them apart
std::vector<AxisMark> axis_marks(double from, double to, int divisions, const std::string& unit);

// a point of the task's plane is beside the path (farther from its centreline than half its
// width), not on it
bool beside_path(const SceneGeometry& geometry, double x_m, double y_m);

// the top view: x to the right, y (forward) up, the scene's view extent fitted into the
// rect with a margin, one scale for both axes
class TopView {
 public:
  TopView(const SceneGeometry& geometry, const Rect& rect);
  Pixel to_screen(double x_m, double y_m) const;
  float pixels_per_m() const { return scale_; }

 private:
  double x0_m_ = 0, y0_m_ = 0;  // the scene point at the rect's origin corner
  float ox_ = 0, oy_ = 0;       // that corner, px (bottom-left of the fitted area)
  float scale_ = 1;
};

// the side view along the task path: horizontal the distance along the path (0 to its
// length), vertical the height from kBelow_m under the top surface to kAbove_m over it
class SideView {
 public:
  static constexpr double kBelow_m = 0.008;
  static constexpr double kAbove_m = 0.004;
  SideView(const SceneGeometry& geometry, const Rect& rect);
  Pixel to_screen(double along_m, double z_m) const;

 private:
  Rect plot_;
  double length_m_ = 0, z0_m_ = 0, z1_m_ = 0;
  float sx_ = 1;
};

}  // namespace enact::viewer
