#pragma once
// Drawing the scene into ImGui draw lists: the top view (the bridge, the workspace, the
// trail, the grid with its masses in contact highlighted), the side view along the path
// (height against the top surface, per-mass forces), the pins as shown, the forces. Pure
// geometry through layout.h, so tests can find what was drawn where.
#include <imgui.h>

#include <vector>

#include "core/viewer/layout.h"
#include "core/viewer/scene_geometry.h"
#include "core/viewer/view_model.h"

namespace enact::viewer {

// the colours (tests look for them in snapshots)
namespace palette {
inline constexpr ImU32 kBackground = IM_COL32(24, 26, 30, 255);
inline constexpr ImU32 kPanel = IM_COL32(34, 37, 43, 255);
inline constexpr ImU32 kTitle = IM_COL32(200, 204, 212, 255);
inline constexpr ImU32 kWorkspace = IM_COL32(80, 86, 96, 255);
inline constexpr ImU32 kBridge = IM_COL32(70, 110, 170, 255);     // the task surface's top
inline constexpr ImU32 kOtherBox = IM_COL32(110, 110, 120, 255);  // other rigid boxes
inline constexpr ImU32 kCentreline = IM_COL32(120, 160, 220, 255);
inline constexpr ImU32 kTrail = IM_COL32(240, 200, 60, 255);
inline constexpr ImU32 kMassFree = IM_COL32(235, 235, 235, 255);
inline constexpr ImU32 kMassContact = IM_COL32(255, 90, 40, 255);
inline constexpr ImU32 kForce = IM_COL32(90, 220, 120, 255);
inline constexpr ImU32 kPinDown = IM_COL32(60, 60, 66, 255);
inline constexpr ImU32 kPinUp = IM_COL32(250, 250, 250, 255);
inline constexpr ImU32 kBeside = IM_COL32(190, 120, 230, 255);    // the body beside the bridge
inline constexpr ImU32 kBridgeBehind = IM_COL32(70, 110, 170, 90); // the bridge behind it
}  // namespace palette

// the radius of a grid mass in the top view, px
float mass_radius(const SceneGeometry& geometry, const TopView& view);

// a panel: background, border and title
void draw_panel(ImDrawList& dl, const Rect& r, const char* title);
void draw_top_view(ImDrawList& dl, const Rect& r, const SceneGeometry& geometry, const ViewModel& model);
void draw_side_view(ImDrawList& dl, const Rect& r, const SceneGeometry& geometry, const ViewModel& model);
// a plot of `values` (oldest first, the newest at the right edge; `slots` of them fill the
// width, `span_s` of time) from 0 to y_max in `unit`, in `r`: `title` above, marks with
// their units on both axes (time in s, 0 the newest)
void draw_plot(ImDrawList& dl, const Rect& r, const std::vector<float>& values, std::size_t slots, double y_max, const char* unit, const char* title,
               double span_s);
void draw_pins(ImDrawList& dl, const Rect& r, const ViewModel& model);
void draw_forces(ImDrawList& dl, const Rect& r, const SceneGeometry& geometry, const ViewModel& model);

}  // namespace enact::viewer
