#pragma once
// Closed triangle meshes as rigid objects: the triangles with their outward normals and the
// angle-weighted pseudo-normals of Baerentzen & Aanaes (2005), "Signed distance computation
// using the angle weighted pseudonormal", which tell inside from outside at the nearest point
// of a closed, consistently wound mesh, whether that point is on a face, an edge or a vertex;
// and a bounding-volume hierarchy (axis-aligned boxes, stored flat) built once at load, so the
// nearest triangle to a point is found in O(log n) without allocating.
#include <array>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/math/vec3.h"

namespace enact::physics {

using math::Vec3;

struct Triangle {
  std::array<int, 3> v{};           // vertex indices, counter-clockwise seen from outside
  Vec3 normal;                      // unit outward normal
  std::array<Vec3, 3> edge_normal;  // edge e (v[e] to v[e+1]): the sum of its two faces' normals
  int source = 0;                   // its index in the file's order (for messages)
};

// a node of the hierarchy: an inner node's left child follows it, `right` names the other;
// a leaf holds `count` consecutive triangles from `first`
struct BvhNode {
  Vec3 low_m;
  Vec3 high_m;
  int first = 0;
  int count = 0;  // 0: an inner node
  int right = -1;
};

struct Mesh {
  std::vector<Vec3> vertices_m;
  std::vector<Vec3> vertex_normals;  // angle-weighted sums of the faces' normals
  std::vector<Triangle> triangles;   // in the hierarchy's leaf order
  std::vector<BvhNode> nodes;        // nodes[0]: the root, bounding the whole mesh
  // each triangle's ring: the triangles sharing a vertex with it (itself included), those of
  // triangle t at ring[ring_first[t], ring_first[t + 1]); where a point goes when it leaves
  // its held triangle
  std::vector<int> ring_first;
  std::vector<int> ring;
};

// a mesh that cannot bound a solid (open, non-manifold, inward, degenerate): the triangle (in
// the file's order; -1: the whole mesh) where it shows, and what to do
struct MeshProblem : std::runtime_error {
  MeshProblem(int triangle_index, const std::string& problem, std::string what_to_do)
      : std::runtime_error(problem), triangle(triangle_index), fix(std::move(what_to_do)) {}
  int triangle;
  std::string fix;
};

// the mesh of these triangles (indices into vertices_m); throws MeshProblem unless they close
// a solid with outward faces: every edge shared by exactly two triangles that run it in
// opposite directions, no zero-area triangle, a positive volume
Mesh build_mesh(std::vector<Vec3> vertices_m, const std::vector<std::array<int, 3>>& triangles);

// a closed solid over a grid of heights (row-major, rows x cols, row 0 at +y, column 0 at -x,
// centred on centre_m's x and y; heights above centre_m.z) down to bottom_z_m: two triangles
// per cell on top and on the flat base, vertical walls; 4 N M + 4 (N + M) triangles for N x M cells
Mesh heightfield_mesh(const std::vector<double>& heights_m, int rows, int cols, double cell_m, const Vec3& centre_m,
                      double bottom_z_m);

// the nearest point of a mesh to a point
struct MeshHit {
  int triangle = -1;
  double distance_m = 0.0;   // to the triangle
  double runner_up_m = 0.0;  // the nearest any other triangle can be (infinity: none)
  Vec3 closest_m;
  Vec3 pseudo_normal;  // of the face, edge or vertex the closest point is on (not unit)
  bool on_face = false;
};

// the triangle nearest to x (through the hierarchy; no allocation)
MeshHit nearest(const Mesh& mesh, const Vec3& x);

// what one search through the hierarchy did: the nodes whose box it tested and the triangles
// it tested (for benches and tests; the step's search counts nothing)
struct SearchCounts {
  long nodes = 0;
  long triangles = 0;
};
// the same search as nearest(mesh, x), the same result bit for bit, its work added to counts
MeshHit nearest(const Mesh& mesh, const Vec3& x, SearchCounts& counts);
// the distance from x to the nearest triangle outside `triangle`'s ring (sharing no vertex
// with it; infinity: none), through the hierarchy; the counted one adds its work to counts
double nearest_beyond(const Mesh& mesh, int triangle, const Vec3& x);
double nearest_beyond(const Mesh& mesh, int triangle, const Vec3& x, SearchCounts& counts);
// the nearest point of one triangle to x (runner_up_m is not set)
MeshHit nearest_on(const Mesh& mesh, int triangle, const Vec3& x);
// the distance from x to the mesh's bounding box (0 inside it)
double distance_to_bounds(const Mesh& mesh, const Vec3& x);

}  // namespace enact::physics
