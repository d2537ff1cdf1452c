#pragma once
// The mesh rows of `enact bench physics`: the bridge's body (CM1) walking over closed
// height-field meshes of 1 mm bumps instead of the bridge, 96 to 99 852 triangles.
#include <array>
#include <string>
#include <vector>

#include "core/math/vec3.h"
#include "core/physics/mesh.h"
#include "core/physics/model.h"

namespace enact::cli::mesh_rows {

// cells a side of the height field (4 N^2 + 8 N triangles)
inline constexpr std::array kMeshCells{4, 15, 49, 157};

// a 60 mm square height field of 1 mm bumps (one every 21 mm) on a 5 mm plateau, `cells` a side
physics::Mesh bumpy_field(int cells);
// the bridge model (body, contact parameters, CM1) with the field instead of its objects
physics::Model on_field(physics::Model m, physics::Mesh field);
// the walk over the field at a rate: a Lissajous figure over 40 x 40 mm, 0.2 to 0.8 mm into the plateau
std::vector<math::Vec3> field_motion(double rate_hz);
// the benchmark's name for a field of `cells` a side: "mesh/<triangles>"
std::string mesh_name(int cells);

}  // namespace enact::cli::mesh_rows
