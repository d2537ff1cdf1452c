// enact bench physics's mesh rows: the bridge's body walking over closed height-field meshes
#include "nodes/enact-bench/bench_physics_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "core/physics/reference.h"

namespace enact::cli::mesh_rows {

namespace reference = physics::reference;

using math::Vec3;

// a 60 mm square height field of 1 mm bumps (one every 21 mm) on a 5 mm plateau, `cells` a side
physics::Mesh bumpy_field(int cells) {
  const double cell_m = 0.06 / cells;
  std::vector<double> heights;
  for (int r = 0; r <= cells; ++r) {
    for (int c = 0; c <= cells; ++c) heights.push_back(0.005 + 0.001 * std::sin(r * cell_m * 300.0) * std::sin(c * cell_m * 300.0));
  }
  return physics::heightfield_mesh(heights, cells + 1, cells + 1, cell_m, {0, 0, 0}, 0.0);
}

// the bridge model (body, contact parameters, CM1) with the field instead of its objects:
// the body's pairs with its first object, now the field
physics::Model on_field(physics::Model m, physics::Mesh field) {
  const int first = m.contacts.front().object;
  std::erase_if(m.contacts, [first](const physics::ContactPair& c) { return c.object != first; });
  for (physics::ContactPair& c : m.contacts) c.object = 0;
  physics::Object o;
  o.name = "field";
  o.type = physics::ObjectType::mesh;
  o.shape = "mesh";
  o.mesh = 0;
  m.objects = {o};
  m.boxes.clear();
  m.meshes = {std::move(field)};
  m.task_surface.clear();
  return m;
}

// the walk over the field: a Lissajous figure over 40 x 40 mm, 0.2 to 0.8 mm into the plateau
std::vector<Vec3> field_motion(double rate_hz) {
  std::vector<Vec3> motion(reference::steps_in(10.0, rate_hz));
  for (std::size_t n = 0; n < motion.size(); ++n) {
    const double phase = 2.0 * std::numbers::pi * static_cast<double>(n) / rate_hz;
    motion[n] = {0.02 * std::sin(0.3 * phase), 0.02 * std::sin(0.2 * phase), 0.0045 + 0.0003 * std::sin(1.1 * phase)};
  }
  return motion;
}

std::string mesh_name(int cells) { return "mesh/" + std::to_string(4 * cells * cells + 8 * cells); }

}  // namespace enact::cli::mesh_rows
