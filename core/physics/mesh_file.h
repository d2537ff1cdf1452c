#pragma once
// Reading the solids of scene objects from files: triangle meshes (binary STL, ASCII STL,
// OBJ) and grids of heights (CSV, 16-bit PNG). Errors are config::Error naming the file, the line (or
// the triangle of a binary STL) and the fix.
#include <string>

#include "core/physics/mesh.h"
#include "core/math/vec3.h"

namespace enact::physics {

// the mesh in a file, each vertex v placed at rotation * (scale * v) + offset_m; refused unless
// it closes a solid with outward faces (build_mesh)
Mesh load_mesh(const std::string& path, double scale, const math::Mat3& rotation, const Vec3& offset_m);

// a grid of heights (m): one row per line, numbers separated by commas, every row as long
struct HeightGrid {
  std::vector<double> heights_m;  // row-major
  int rows = 0;
  int cols = 0;
};
HeightGrid read_heights(const std::string& path);
// a grid of heights from a 16-bit grayscale PNG: row 0 the top row, a pixel's value times
// max_height_m / 65535
HeightGrid read_png_heights(const std::string& path, double max_height_m);

}  // namespace enact::physics
