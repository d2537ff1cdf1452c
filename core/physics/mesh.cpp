#include "core/physics/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>
#include <utility>

namespace enact::physics {
namespace {

using math::kInfinity;
// a leaf of the hierarchy holds at most this many triangles
constexpr int kLeafSize = 4;
// the deepest the hierarchy can be: a median split halves the triangles at each level
constexpr int kMaxDepth = 64;

Vec3 cross(const Vec3& a, const Vec3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
// divided, not multiplied by the inverse: an axis-aligned normal comes out exact
Vec3 unit(const Vec3& v) {
  const double n = norm(v);
  return {v.x / n, v.y / n, v.z / n};
}
Vec3 lower(const Vec3& a, const Vec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
Vec3 upper(const Vec3& a, const Vec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

// the angle at vertex a of the triangle a, b, c
double angle_at(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = b - a, w = c - a;
  return std::atan2(norm(cross(u, w)), dot(u, w));
}

// squared distance from x to an axis-aligned box (0 inside)
double box_distance2(const Vec3& low, const Vec3& high, const Vec3& x) {
  double d2 = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double v = component(x, axis);
    const double out = std::max({component(low, axis) - v, 0.0, v - component(high, axis)});
    d2 += out * out;
  }
  return d2;
}

std::string text(const Vec3& v) {
  std::ostringstream s;
  s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

// every edge of a closed mesh runs once each way: the triangle across each edge
std::vector<std::array<int, 3>> neighbours(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles) {
  auto edge_text = [&](int a, int b) { return "the edge from " + text(vertices[a]) + " to " + text(vertices[b]); };
  std::map<std::pair<int, int>, int> edge_owner;
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t) {
    for (int e = 0; e < 3; ++e) {
      const std::pair<int, int> edge{triangles[t][e], triangles[t][(e + 1) % 3]};
      if (!edge_owner.emplace(edge, t).second) {
        throw MeshProblem(t, edge_text(edge.first, edge.second) + " runs the same way in this face and an earlier one (more than two faces meet there, or one is wound the other way)",
                         "wind every face counter-clockwise seen from outside, and let each edge join exactly two faces");
      }
    }
  }
  std::vector<std::array<int, 3>> across(triangles.size());
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t) {
    for (int e = 0; e < 3; ++e) {
      const auto it = edge_owner.find({triangles[t][(e + 1) % 3], triangles[t][e]});
      if (it == edge_owner.end()) {
        throw MeshProblem(t, "the mesh is open: " + edge_text(triangles[t][e], triangles[t][(e + 1) % 3]) + " belongs to this face only",
                         "close the mesh (a contact needs an inside: a solid bounded all round); fill its holes in a mesh editor");
      }
      across[t][e] = it->second;
    }
  }
  return across;
}

// the hierarchy over triangles order[first, first + count): nodes appended depth first
void build_node(Mesh& mesh, std::vector<int>& order, const std::vector<Vec3>& centroids, int first, int count, int depth) {
  const int index = static_cast<int>(mesh.nodes.size());
  mesh.nodes.push_back({});
  Vec3 low{kInfinity, kInfinity, kInfinity}, high = -low, c_low = low, c_high = high;
  for (int i = first; i < first + count; ++i) {
    for (int k : mesh.triangles[order[i]].v) {
      low = lower(low, mesh.vertices_m[k]);
      high = upper(high, mesh.vertices_m[k]);
    }
    c_low = lower(c_low, centroids[order[i]]);
    c_high = upper(c_high, centroids[order[i]]);
  }
  mesh.nodes[index].low_m = low;
  mesh.nodes[index].high_m = high;
  if (count <= kLeafSize || depth == kMaxDepth) {
    mesh.nodes[index].first = first;
    mesh.nodes[index].count = count;
    return;
  }
  // split at the median centroid along the longest extent of the centroids
  const Vec3 extent = c_high - c_low;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const int half = count / 2;
  std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                   [&](int a, int b) { return component(centroids[a], axis) < component(centroids[b], axis); });
  build_node(mesh, order, centroids, first, half, depth + 1);
  mesh.nodes[index].right = static_cast<int>(mesh.nodes.size());
  build_node(mesh, order, centroids, first + half, count - half, depth + 1);
}

// the rings, from the triangles around each vertex (in the hierarchy's order)
void build_rings(Mesh& mesh) {
  std::vector<std::vector<int>> around(mesh.vertices_m.size());
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
    for (int k : mesh.triangles[t].v) around[k].push_back(t);
  }
  mesh.ring_first.assign(1, 0);
  std::vector<int> ring;
  for (const Triangle& tri : mesh.triangles) {
    ring.clear();
    for (int k : tri.v) ring.insert(ring.end(), around[k].begin(), around[k].end());
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    mesh.ring.insert(mesh.ring.end(), ring.begin(), ring.end());
    mesh.ring_first.push_back(static_cast<int>(mesh.ring.size()));
  }
}

bool share_a_vertex(const Triangle& a, const Triangle& b) {
  for (int i : a.v) {
    if (i == b.v[0] || i == b.v[1] || i == b.v[2]) return true;
  }
  return false;
}

void build_hierarchy(Mesh& mesh) {
  std::vector<Vec3> centroids;
  for (const Triangle& t : mesh.triangles) centroids.push_back((mesh.vertices_m[t.v[0]] + mesh.vertices_m[t.v[1]] + mesh.vertices_m[t.v[2]]) * (1.0 / 3.0));
  std::vector<int> order(mesh.triangles.size());
  std::iota(order.begin(), order.end(), 0);
  build_node(mesh, order, centroids, 0, static_cast<int>(order.size()), 0);
  std::vector<Triangle> sorted;
  for (int t : order) sorted.push_back(mesh.triangles[t]);
  mesh.triangles = std::move(sorted);
}

}  // namespace

Mesh build_mesh(std::vector<Vec3> vertices_m, const std::vector<std::array<int, 3>>& triangles) {
  if (triangles.empty()) throw MeshProblem(-1, "the mesh has no triangles", "give the file's faces");
  Mesh mesh;
  mesh.vertices_m = std::move(vertices_m);
  const std::vector<std::array<int, 3>> across = neighbours(mesh.vertices_m, triangles);
  double volume = 0.0;
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t) {
    const auto& v = triangles[t];
    const Vec3 &a = mesh.vertices_m[v[0]], &b = mesh.vertices_m[v[1]], &c = mesh.vertices_m[v[2]];
    const Vec3 n = cross(b - a, c - a);
    if (!(norm(n) > 0.0)) throw MeshProblem(t, "this face has no area (its corners are on one line)", "remove it, or move its corners apart");
    volume += dot(a, cross(b, c)) / 6.0;
    mesh.triangles.push_back({v, unit(n), {}, t});
  }
  if (!(volume > 0.0)) throw MeshProblem(-1, "the mesh's faces point inwards (its volume is negative)", "reverse the corner order of every face (counter-clockwise seen from outside)");
  // pseudo-normals: an edge's, the sum of its two faces' normals; a vertex's, the faces' normals
  // weighted by their angles there
  mesh.vertex_normals.assign(mesh.vertices_m.size(), Vec3{});
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Triangle& tri = mesh.triangles[t];
    for (int e = 0; e < 3; ++e) {
      tri.edge_normal[e] = tri.normal + mesh.triangles[across[t][e]].normal;
      const Vec3& corner = mesh.vertices_m[tri.v[e]];
      mesh.vertex_normals[tri.v[e]] += tri.normal * angle_at(corner, mesh.vertices_m[tri.v[(e + 1) % 3]], mesh.vertices_m[tri.v[(e + 2) % 3]]);
    }
  }
  build_hierarchy(mesh);
  build_rings(mesh);
  return mesh;
}

Mesh heightfield_mesh(const std::vector<double>& heights_m, int rows, int cols, double cell_m, const Vec3& centre_m, double bottom_z_m) {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  // the top grid, then the same grid at the base: small triangles only, so that the
  // hierarchy's boxes stay small (one large base triangle would widen every box holding it)
  const double x0 = centre_m.x - 0.5 * (cols - 1) * cell_m, y0 = centre_m.y + 0.5 * (rows - 1) * cell_m;
  for (int layer = 0; layer < 2; ++layer) {
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) vertices.push_back({x0 + c * cell_m, y0 - r * cell_m, layer == 0 ? centre_m.z + heights_m[r * cols + c] : bottom_z_m});
    }
  }
  auto top = [cols](int r, int c) { return r * cols + c; };
  auto base = [rows, cols](int r, int c) { return (rows + r) * cols + c; };
  for (int r = 0; r + 1 < rows; ++r) {
    for (int c = 0; c + 1 < cols; ++c) {
      // seen from above, row r is north of row r + 1: counter-clockwise is west, south, east;
      // the base is seen from below
      triangles.push_back({top(r, c), top(r + 1, c), top(r + 1, c + 1)});
      triangles.push_back({top(r, c), top(r + 1, c + 1), top(r, c + 1)});
      triangles.push_back({base(r, c), base(r + 1, c + 1), base(r + 1, c)});
      triangles.push_back({base(r, c), base(r, c + 1), base(r + 1, c + 1)});
    }
  }
  // the walls under the boundary, counter-clockwise seen from above: down the west side, east
  // along the south, up the east side, west along the north (the outside on the right)
  std::vector<std::pair<int, int>> ring;
  for (int r = 0; r + 1 < rows; ++r) ring.push_back({r, 0});
  for (int c = 0; c + 1 < cols; ++c) ring.push_back({rows - 1, c});
  for (int r = rows - 1; r > 0; --r) ring.push_back({r, cols - 1});
  for (int c = cols - 1; c > 0; --c) ring.push_back({0, c});
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const auto [ri, ci] = ring[i];
    const auto [rj, cj] = ring[(i + 1) % ring.size()];
    triangles.push_back({top(ri, ci), base(ri, ci), base(rj, cj)});
    triangles.push_back({top(ri, ci), base(rj, cj), top(rj, cj)});
  }
  return build_mesh(std::move(vertices), triangles);
}

MeshHit nearest_on(const Mesh& mesh, int triangle, const Vec3& x) {
  // the closest point of a triangle by its Voronoi regions (vertex, edge or face), in the
  // order of Ericson (2005), "Real-Time Collision Detection", 5.1.5
  const Triangle& t = mesh.triangles[triangle];
  const Vec3 &a = mesh.vertices_m[t.v[0]], &b = mesh.vertices_m[t.v[1]], &c = mesh.vertices_m[t.v[2]];
  MeshHit hit;
  hit.triangle = triangle;
  auto at_vertex = [&](int k) {
    hit.closest_m = mesh.vertices_m[t.v[k]];
    hit.pseudo_normal = mesh.vertex_normals[t.v[k]];
  };
  auto on_edge = [&](int e, const Vec3& p) {
    hit.closest_m = p;
    hit.pseudo_normal = t.edge_normal[e];
  };
  const Vec3 ab = b - a, ac = c - a, ap = x - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  const Vec3 bp = x - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  const Vec3 cp = x - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  if (d1 <= 0.0 && d2 <= 0.0) at_vertex(0);
  else if (d3 >= 0.0 && d4 <= d3) at_vertex(1);
  else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) on_edge(0, a + ab * (d1 / (d1 - d3)));
  else if (d6 >= 0.0 && d5 <= d6) at_vertex(2);
  else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) on_edge(2, a + ac * (d2 / (d2 - d6)));
  else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) on_edge(1, b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  else {
    // inside the face: the distance to its plane
    const double height = dot(t.normal, ap);
    hit.closest_m = x - t.normal * height;
    hit.pseudo_normal = t.normal;
    hit.on_face = true;
    hit.distance_m = std::abs(height);
    return hit;
  }
  hit.distance_m = norm(x - hit.closest_m);
  return hit;
}

namespace {

// nearest() and nearest_beyond(): one body for the step's searches and the counted ones
// (kCount false compiles the counting away, so the step's searches do no extra work). kBeyond:
// only the triangles outside `ring_of`'s ring count, and only the nearest's distance is needed
template <bool kCount, bool kBeyond>
MeshHit search(const Mesh& mesh, const Vec3& x, int ring_of, SearchCounts* counts) {
  MeshHit best;
  best.distance_m = kInfinity;
  best.runner_up_m = kInfinity;
  // depth first, nearer child first; a node is skipped when it cannot hold a triangle nearer
  // than the runner-up (so the runner-up is exact too; beyond a ring, than the nearest)
  int stack[kMaxDepth + 2];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = mesh.nodes[stack[--top]];
    if constexpr (kCount) ++counts->nodes;
    const double bound = kBeyond ? best.distance_m : best.runner_up_m;
    if (box_distance2(node.low_m, node.high_m, x) >= bound * bound) continue;
    if (node.count > 0) {
      for (int t = node.first; t < node.first + node.count; ++t) {
        if (kBeyond && share_a_vertex(mesh.triangles[t], mesh.triangles[ring_of])) continue;
        if constexpr (kCount) ++counts->triangles;
        const MeshHit hit = nearest_on(mesh, t, x);
        if (hit.distance_m < best.distance_m) {
          const double runner_up = best.distance_m;
          best = hit;
          best.runner_up_m = runner_up;
        } else {
          best.runner_up_m = std::min(best.runner_up_m, hit.distance_m);
        }
      }
      continue;
    }
    const int left = static_cast<int>(&node - mesh.nodes.data()) + 1;
    const bool left_first = box_distance2(mesh.nodes[left].low_m, mesh.nodes[left].high_m, x) <=
                            box_distance2(mesh.nodes[node.right].low_m, mesh.nodes[node.right].high_m, x);
    stack[top++] = left_first ? node.right : left;
    stack[top++] = left_first ? left : node.right;
  }
  return best;
}

}  // namespace

MeshHit nearest(const Mesh& mesh, const Vec3& x) { return search<false, false>(mesh, x, -1, nullptr); }

MeshHit nearest(const Mesh& mesh, const Vec3& x, SearchCounts& counts) { return search<true, false>(mesh, x, -1, &counts); }

double nearest_beyond(const Mesh& mesh, int triangle, const Vec3& x) { return search<false, true>(mesh, x, triangle, nullptr).distance_m; }

double nearest_beyond(const Mesh& mesh, int triangle, const Vec3& x, SearchCounts& counts) {
  return search<true, true>(mesh, x, triangle, &counts).distance_m;
}

double distance_to_bounds(const Mesh& mesh, const Vec3& x) { return std::sqrt(box_distance2(mesh.nodes[0].low_m, mesh.nodes[0].high_m, x)); }

}  // namespace enact::physics
