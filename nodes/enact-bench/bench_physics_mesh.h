#pragma once
// The mesh rows of `enact bench physics`: the bridge's body (CM1) walking over closed
// height-field meshes of 1 mm bumps instead of the bridge, about 10^2 to 10^5 triangles, in two
// sets: the same 60 mm square refined (smaller triangles near the body as the count grows) and
// a field of fixed 15 mm cells grown around it (the same triangles near the body, only the
// hierarchy deepens: the O(log n) claim of a bounding-volume hierarchy).
#include <array>
#include <string>
#include <vector>

#include "core/math/vec3.h"
#include "core/physics/mesh.h"
#include "core/physics/model.h"

namespace enact::cli::mesh_rows {

// how a set's fields grow
enum class FieldSet { refined, fixed_cell };

struct FieldSpec {
  FieldSet set = FieldSet::refined;
  int cells = 0;  // a side (4 N^2 + 8 N triangles)
  double cell_m = 0.0;
  int margin = 0;  // cells grown on each side of the 60 mm square
};

// the refined set: the 60 mm square, `cells` a side
inline constexpr std::array kRefinedCells{4, 15, 49, 157};
// the fixed-cell set: 15 mm cells, the 60 mm square (4 cells) grown by this many on each
// side: 4, 16, 50 and 158 cells a side
inline constexpr std::array kFixedCellMargins{0, 6, 23, 77};
inline constexpr double kFixedCell_m = 0.015;

// the refined set's fields, then the fixed-cell set's
std::vector<FieldSpec> field_specs();
const char* to_string(FieldSet set);
physics::Mesh field_mesh(const FieldSpec& spec);
// the bridge model (body, contact parameters, CM1) with the field instead of its objects
physics::Model on_field(physics::Model m, physics::Mesh field);
// the walk over the field at a rate: a Lissajous figure over 40 x 40 mm, 0.2 to 0.8 mm into the plateau
std::vector<math::Vec3> field_motion(double rate_hz);
// the benchmark's name for a field: "mesh/<set>/<triangles>"
std::string mesh_name(const FieldSpec& spec);

// what the step did over one pass of the walk, per contact pair and step (counted outside the
// timing: the step itself counts nothing)
struct LookupCounts {
  long pair_steps = 0;
  long searches = 0;    // steps that searched the hierarchy
  long ring_steps = 0;  // steps that took the nearest of the last search's ring (the rest kept the held triangle)
  long in_contact = 0;  // pair steps inside the mesh
  physics::SearchCounts nearest;  // over those searches: boxes and triangles the nearest's search tested
  physics::SearchCounts beyond;   // and the search for the nearest beyond its ring
  int depth = 0;                  // the hierarchy's depth (levels below the root)
  double per_pair_step(long n) const { return static_cast<double>(n) / static_cast<double>(pair_steps); }
  double held_share() const { return 1.0 - per_pair_step(searches + ring_steps); }
  double per_search(long n) const { return searches > 0 ? static_cast<double>(n) / static_cast<double>(searches) : 0.0; }
};
// the field model (on_field) stepped along the walk once
LookupCounts count_lookups(const physics::Model& field, const std::vector<math::Vec3>& walk);

}  // namespace enact::cli::mesh_rows
