#include "core/physics/mesh_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include <png.h>

#include "core/config/yaml.h"

namespace enact::physics {
namespace {

// the triangles of a file, with where each came from
struct Soup {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::string> where;  // per triangle: "FILE:LINE" or "FILE (triangle N)"
};

[[noreturn]] void fail(const std::string& where, const std::string& problem, const std::string& fix) {
  throw config::Error(where + ": " + problem + "\n  fix: " + fix);
}

std::string at_line(const std::string& path, int line) { return path + ":" + std::to_string(line); }

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file", "check the path (relative to the scene file)");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// a polygon's corners as a fan of triangles (convex polygons)
void add_polygon(Soup& soup, const std::vector<int>& corners, const std::string& where) {
  if (corners.size() < 3) fail(where, "a face needs at least 3 corners", "give each face 3 or more vertices");
  for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
    soup.triangles.push_back({corners[0], corners[k], corners[k + 1]});
    soup.where.push_back(where);
  }
}

// the next number of a line; fails naming the line
double number(std::istringstream& words, const std::string& where, const char* what) {
  std::string word;
  words >> word;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || *end != '\0' || !std::isfinite(v)) fail(where, std::string(what) + " needs three finite numbers", "write e.g. " + std::string(what) + " 0.01 0 0.02");
  return v;
}

// STL repeats a vertex in every triangle that shares it: equal coordinates are one vertex
class Welder {
 public:
  explicit Welder(Soup& soup) : soup_(soup) {}
  int add(const Vec3& v) {
    const auto [it, added] = index_.emplace(std::make_tuple(v.x, v.y, v.z), static_cast<int>(soup_.vertices.size()));
    if (added) soup_.vertices.push_back(v);
    return it->second;
  }

 private:
  Soup& soup_;
  std::map<std::tuple<double, double, double>, int> index_;
};

// binary STL: an 80-byte header, a little-endian triangle count, then 50 bytes per triangle
// (normal, three corners as floats, a 2-byte attribute)
bool binary_stl(const std::string& path, const std::string& bytes, Soup& soup) {
  if (bytes.size() < 84) return false;
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  if (bytes.size() != 84 + 50 * static_cast<std::size_t>(count)) return false;
  Welder welder(soup);
  for (std::uint32_t t = 0; t < count; ++t) {
    std::array<int, 3> corners{};
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, bytes.data() + 84 + 50 * static_cast<std::size_t>(t) + 12 * (k + 1), sizeof xyz);
      corners[k] = welder.add({xyz[0], xyz[1], xyz[2]});
    }
    soup.triangles.push_back(corners);
    soup.where.push_back(path + " (triangle " + std::to_string(t + 1) + ")");
  }
  return true;
}

// ASCII STL: facets of `vertex x y z` lines between `outer loop` and `endloop`
void ascii_stl(const std::string& path, const std::string& text, Soup& soup) {
  Welder welder(soup);
  std::istringstream lines(text);
  std::string line;
  std::vector<int> loop;
  int loop_line = 0;
  for (int n = 1; std::getline(lines, line); ++n) {
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "outer") {
      loop.clear();
      loop_line = n;
    } else if (word == "vertex") {
      const std::string where = at_line(path, n);
      const double x = number(words, where, "vertex"), y = number(words, where, "vertex"), z = number(words, where, "vertex");
      loop.push_back(welder.add({x, y, z}));
    } else if (word == "endloop") {
      add_polygon(soup, loop, at_line(path, loop_line));
    }
  }
}

// OBJ: `v x y z` vertices and `f i j k ...` faces (indices from 1, negative from the end,
// `i/t/n` forms); everything else (normals, textures, groups) is ignored
void obj(const std::string& path, const std::string& text, Soup& soup) {
  std::istringstream lines(text);
  std::string line;
  for (int n = 1; std::getline(lines, line); ++n) {
    std::istringstream words(line);
    std::string word;
    words >> word;
    const std::string where = at_line(path, n);
    if (word == "v") {
      const double x = number(words, where, "v"), y = number(words, where, "v"), z = number(words, where, "v");
      soup.vertices.push_back({x, y, z});
    } else if (word == "f") {
      std::vector<int> corners;
      const int count = static_cast<int>(soup.vertices.size());
      for (std::string corner; words >> corner;) {
        char* end = nullptr;
        const long i = std::strtol(corner.c_str(), &end, 10);
        const long index = i < 0 ? count + i : i - 1;
        if (end == corner.c_str() || (*end != '\0' && *end != '/') || i == 0 || index < 0 || index >= count) {
          fail(where, "face corner '" + corner + "' is not a vertex defined above", "number vertices from 1 in the order of the v lines (negative: from the last)");
        }
        corners.push_back(static_cast<int>(index));
      }
      add_polygon(soup, corners, where);
    }
  }
}

bool ends_with(const std::string& s, const std::string& end) {
  return s.size() >= end.size() && std::equal(end.rbegin(), end.rend(), s.rbegin(), [](char a, char b) { return std::tolower(a) == b; });
}

}  // namespace

Mesh load_mesh(const std::string& path, double scale, const math::Mat3& rotation, const Vec3& offset_m) {
  const std::string bytes = read_all(path);
  Soup soup;
  if (ends_with(path, ".obj")) obj(path, bytes, soup);
  else if (!ends_with(path, ".stl")) fail(path, "unknown mesh format", "give a binary or ASCII STL (.stl) or an OBJ (.obj) file");
  else if (!binary_stl(path, bytes, soup)) ascii_stl(path, bytes, soup);
  for (Vec3& v : soup.vertices) v = rotation * (v * scale) + offset_m;
  try {
    return build_mesh(std::move(soup.vertices), soup.triangles);
  } catch (const MeshProblem& p) {
    fail(p.triangle < 0 ? path : soup.where[p.triangle], p.what(), p.fix);
  }
}

// a 16-bit grayscale PNG: row 0 at the top (+y), each pixel's value times max_height_m / 65535
HeightGrid read_png_heights(const std::string& path, double max_height_m) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) fail(path, std::string("cannot read it as a PNG: ") + image.message, "give a 16-bit grayscale PNG");
  if (image.format != PNG_FORMAT_LINEAR_Y) {
    png_image_free(&image);
    fail(path, "the PNG is not 16-bit grayscale", "save it as 16-bit grayscale (one channel, no alpha): 8 bits give only 256 heights");
  }
  std::vector<png_uint_16> pixels(PNG_IMAGE_SIZE(image) / sizeof(png_uint_16));
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr)) fail(path, std::string("cannot read the PNG: ") + image.message, "give a 16-bit grayscale PNG");
  HeightGrid grid{{}, static_cast<int>(image.height), static_cast<int>(image.width)};
  for (png_uint_16 p : pixels) grid.heights_m.push_back(p * (max_height_m / 65535.0));
  if (grid.rows < 2 || grid.cols < 2) fail(path, "a height map needs at least 2 x 2 pixels", "give a larger image");
  return grid;
}

HeightGrid read_heights(const std::string& path) {
  std::istringstream lines(read_all(path));
  HeightGrid grid;
  std::string line;
  for (int n = 1; std::getline(lines, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream cells(line);
    int cols = 0;
    for (std::string cell; std::getline(cells, cell, ',');) {
      char* end = nullptr;
      const double h = std::strtod(cell.c_str(), &end);
      while (*end == ' ' || *end == '\t' || *end == '\r') ++end;
      if (end == cell.c_str() || *end != '\0' || !std::isfinite(h)) fail(at_line(path, n), "'" + cell + "' is not a height", "write finite heights in metres, separated by commas");
      grid.heights_m.push_back(h);
      ++cols;
    }
    if (grid.rows > 0 && cols != grid.cols) {
      fail(at_line(path, n), "this row has " + std::to_string(cols) + " heights, the first had " + std::to_string(grid.cols), "give every row as many heights");
    }
    grid.cols = cols;
    ++grid.rows;
  }
  if (grid.rows < 2 || grid.cols < 2) fail(path, "a height map needs at least 2 rows of at least 2 heights", "give a grid of heights, one row per line");
  return grid;
}

}  // namespace enact::physics
