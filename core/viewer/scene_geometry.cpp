#include "core/viewer/scene_geometry.h"

#include <algorithm>

#include "core/devices/device_profile.h"
#include "core/physics/scene.h"

namespace enact::viewer {
namespace {

// around boxes and the body when there is no device workspace
constexpr double kMargin_m = 0.005;

void grow(task::Point2& lo, task::Point2& hi, double x, double y) {
  lo = {std::min(lo.x_m, x), std::min(lo.y_m, y)};
  hi = {std::max(hi.x_m, x), std::max(hi.y_m, y)};
}

// a mesh seen from above: its triangles that face up (a triangle is a face whose last corner
// is repeated)
void add_mesh_faces(const physics::Mesh& mesh, SceneGeometry& g) {
  for (const physics::Triangle& t : mesh.triangles) {
    if (t.normal.z <= 0.0) continue;
    TopFace f;
    for (int i = 0; i < 4; ++i) {
      const math::Vec3& v = mesh.vertices_m[t.v[std::min(i, 2)]];
      f.corner[i] = {v.x, v.y};
      f.top_z_m = i == 0 ? v.z : std::max(f.top_z_m, v.z);
    }
    g.faces.push_back(f);
  }
}

}  // namespace

SceneGeometry geometry_of(const physics::Model& m) {
  SceneGeometry g;
  g.name = m.name;
  g.task_surface = m.task_surface;
  const int surface = m.task_surface.empty() ? -1 : m.find_object(m.task_surface);
  // the boxes' top faces, the meshes' faces that look up
  for (std::size_t o = 0; o < m.objects.size(); ++o) {
    const physics::Object& obj = m.objects[o];
    if (obj.type == physics::ObjectType::plane) {
      if (obj.plane_normal.z > 0.99) g.floor_z_m = std::max(g.floor_z_m, obj.plane_point_m.z);
      continue;
    }
    if (obj.type == physics::ObjectType::mesh) add_mesh_faces(m.meshes[obj.mesh], g);
    if (obj.type == physics::ObjectType::capsule) {
      g.rounds.push_back({{obj.axis_from_m.x, obj.axis_from_m.y}, {obj.axis_to_m.x, obj.axis_to_m.y}, obj.radius_m,
                          std::max(obj.axis_from_m.z, obj.axis_to_m.z) + obj.radius_m, static_cast<int>(o) == surface});
    }
    for (int b = obj.first_box; b < obj.first_box + obj.box_count; ++b) {
      const physics::Box& box = m.boxes[b];
      const math::Vec3& h = box.half_extents_m;
      TopFace f;
      const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
      for (int i = 0; i < 4; ++i) {
        const math::Vec3 c = box.center_m + box.rotation * math::Vec3{sx[i] * h.x, sy[i] * h.y, h.z};
        f.corner[i] = {c.x, c.y};
        f.top_z_m = c.z;
      }
      f.task_surface = static_cast<int>(o) == surface;
      g.faces.push_back(f);
    }
  }
  // the task's line (a path object's centreline, or the line given on another object)
  if (surface >= 0) {
    std::vector<task::Point2> line;
    for (const math::Vec3& p : m.task_path.centerline_m) line.push_back({p.x, p.y});
    g.path = task::Polyline(line);
    g.has_path = true;
    g.path_width_m = m.task_path.width_m;
    g.top_z_m = m.task_path.top_z_m;
  }
  // the body
  if (!m.proxies.empty()) {
    const physics::Proxy& body = m.proxies[0];
    g.rows = body.rows;
    g.cols = body.cols;
    for (int i = 0; i < body.rows * body.cols; ++i) g.grid_offsets_m.push_back(m.points[body.first_body + i].offset_m);
  }
  // the view: the workspace, else what there is
  if (const auto profile = devices::find_device_profile(m.device_profile)) {
    g.view_min_m = {profile->workspace_min_m.x, profile->workspace_min_m.y};
    g.view_max_m = {profile->workspace_max_m.x, profile->workspace_max_m.y};
    return g;
  }
  task::Point2 lo{1e9, 1e9}, hi{-1e9, -1e9};
  for (const TopFace& f : g.faces) {
    for (const task::Point2& c : f.corner) grow(lo, hi, c.x_m, c.y_m);
  }
  for (const RoundTop& round : g.rounds) {
    for (const task::Point2& c : {round.from, round.to}) {
      grow(lo, hi, c.x_m - round.radius_m, c.y_m - round.radius_m);
      grow(lo, hi, c.x_m + round.radius_m, c.y_m + round.radius_m);
    }
  }
  if (!m.proxies.empty()) {
    const math::Vec3& start = m.points[m.proxies[0].point].position_m;
    grow(lo, hi, start.x, start.y);
  }
  if (lo.x_m > hi.x_m) lo = hi = {0.0, 0.0};
  g.view_min_m = {lo.x_m - kMargin_m, lo.y_m - kMargin_m};
  g.view_max_m = {hi.x_m + kMargin_m, hi.y_m + kMargin_m};
  return g;
}

SceneGeometry load_geometry(const std::string& scene_file) { return geometry_of(physics::load_scene(scene_file)); }

}  // namespace enact::viewer
