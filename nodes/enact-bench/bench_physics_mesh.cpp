// enact bench physics's mesh rows: the bridge's body walking over closed height-field meshes
#include "nodes/enact-bench/bench_physics_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "core/physics/reference.h"
#include "core/physics/state.h"

namespace enact::cli::mesh_rows {

namespace reference = physics::reference;

using math::Vec3;

std::vector<FieldSpec> field_specs() {
  std::vector<FieldSpec> specs;
  for (int cells : kRefinedCells) specs.push_back({FieldSet::refined, cells, 0.06 / cells, 0});
  for (int margin : kFixedCellMargins) specs.push_back({FieldSet::fixed_cell, 4 + 2 * margin, kFixedCell_m, margin});
  return specs;
}

const char* to_string(FieldSet set) { return set == FieldSet::refined ? "refined" : "fixed_cell"; }

physics::Mesh field_mesh(const FieldSpec& spec) { return reference::bumpy_field(spec.cells, spec.cell_m, spec.margin); }

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

std::string mesh_name(const FieldSpec& spec) {
  return std::string("mesh/") + to_string(spec.set) + "/" + std::to_string(4 * spec.cells * spec.cells + 8 * spec.cells);
}

namespace {

// levels below node `index` (a leaf: 0); the left child follows its parent
int depth_below(const physics::Mesh& mesh, int index) {
  const physics::BvhNode& node = mesh.nodes[index];
  if (node.count > 0) return 0;
  return 1 + std::max(depth_below(mesh, index + 1), depth_below(mesh, node.right));
}

}  // namespace

LookupCounts count_lookups(const physics::Model& field, const std::vector<Vec3>& walk) {
  const physics::Mesh& mesh = field.meshes[0];
  physics::State s = physics::make_state(field);
  LookupCounts counts;
  counts.depth = depth_below(mesh, 0);
  std::vector<Vec3> hold_before(field.contacts.size()), ring_before(field.contacts.size());
  for (const Vec3& at : walk) {
    for (std::size_t k = 0; k < field.contacts.size(); ++k) {
      hold_before[k] = s.contacts[k].hold_at_m;
      ring_before[k] = s.contacts[k].ring_at_m;
    }
    s.proxy_position_m[0] = at;
    physics::step(field, s);
    for (std::size_t k = 0; k < field.contacts.size(); ++k) {
      const physics::ContactState& c = s.contacts[k];
      const Vec3& x = s.x[field.contacts[k].point];
      ++counts.pair_steps;
      counts.in_contact += c.active;
      // a search centres the ring on the point, and a search or a ring step the next hold; a
      // held step leaves both where they were (exact but for a point standing exactly where
      // it last searched)
      if (c.ring_at_m == x && !(ring_before[k] == x)) {
        ++counts.searches;
        physics::nearest(mesh, x, counts.nearest);
        if (c.ring_of >= 0) physics::nearest_beyond(mesh, c.ring_of, x, counts.beyond);
      } else if (c.hold_at_m == x && !(hold_before[k] == x)) {
        ++counts.ring_steps;
      }
    }
  }
  return counts;
}

}  // namespace enact::cli::mesh_rows
