#pragma once
// What the viewer draws of a scene, taken from its file (the same file the simulator
// loaded; `enact-viewer --scene`): the rigid boxes, meshes (and height maps), spheres and
// capsules seen from above, the task path and its top surface, the floor, the device
// workspace, and the exploratory body's grid.
#include <string>
#include <vector>

#include "core/graph/kept_files.h"
#include "core/physics/model.h"
#include "core/task/polyline.h"

namespace enact::viewer {

using graph::find_scene;
using graph::NamedScene;
using graph::sim_of_scene_key;

// a box's top face seen from above: its 4 corners (x, y), in order around it
struct TopFace {
  task::Point2 corner[4];
  double top_z_m = 0.0;
  bool task_surface = false;  // part of the task's path (the bridge)
};

// a sphere or a capsule seen from above: a disc, or two discs joined by a band (its axis's
// ends, x and y)
struct RoundTop {
  task::Point2 from, to;
  double radius_m = 0.0;
  double top_z_m = 0.0;
  bool task_surface = false;
};

struct SceneGeometry {
  std::string name;
  std::string task_surface;           // the object the task is about ("": no task)
  // what the top view shows, m: the device workspace when the scene names a device profile,
  // else the boxes and the body's start with a margin
  task::Point2 view_min_m, view_max_m;
  double floor_z_m = 0.0;             // the highest plane under the body (0 without one)
  std::vector<TopFace> faces;         // every box of every box object, every upward mesh triangle
  std::vector<RoundTop> rounds;       // every sphere and capsule
  bool has_path = false;              // the scene has a task path
  task::Polyline path;                // its centreline
  double path_width_m = 0.0;
  double top_z_m = 0.0;               // its top surface
  int rows = 0, cols = 0;             // the body's grid (pin i = row * cols + col)
  std::vector<math::Vec3> grid_offsets_m;  // grid mass i relative to the body centre
};

// from a loaded model (a model without a body gives an empty grid)
SceneGeometry geometry_of(const physics::Model& model);

// the scene file, loaded and checked (config::Error on bad input)
SceneGeometry load_geometry(const std::string& scene_file);

}  // namespace enact::viewer
