// Triangle meshes (core/physics/mesh.h): the contact of a point with a closed mesh on hard
// cases (grazing a face, exactly on an edge and a vertex, deep inside, a thin wall, moving
// across edges), the held triangle against the full search, a box written as 12 triangles
// against the box object, a step that allocates nothing, and a search whose work grows with
// log(triangles) when a field grows around triangles of one size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/physics/reference.h"
#include "tests/physics/models.h"
#include "tests/support/alloc_guard.h"

namespace enact::physics {
namespace {

using models::same_bits;

constexpr double kStiffness_n_per_m = 6000.0;

// a box 20 x 16 x 10 mm standing on z = 0
const Vec3 kCentre{0.0, 0.0, 0.005};
const Vec3 kHalf{0.010, 0.008, 0.005};

using models::Probe;
using models::probe;

Model box_mesh_model() {
  Model m;
  models::add_mesh(m, "box", models::box_mesh(kCentre, kHalf));
  return m;
}

TEST(Mesh, GrazingAFaceTouchesOnlyBelowIt) {
  const Model m = box_mesh_model();
  const Vec3 top{0.003, -0.002, 0.010};
  EXPECT_EQ(probe(m, 0, top + Vec3{0, 0, 1e-9}).depth_m, 0.0);
  EXPECT_EQ(probe(m, 0, top).depth_m, 0.0);
  const Probe below = probe(m, 0, top - Vec3{0, 0, 1e-9});
  EXPECT_NEAR(below.depth_m, 1e-9, 1e-15);
  EXPECT_EQ(below.normal, (Vec3{0, 0, 1}));
  // a side face, grazed from inside
  const Probe side = probe(m, 0, {0.010 - 2e-9, 0.001, 0.004});
  EXPECT_NEAR(side.depth_m, 2e-9, 1e-15);
  EXPECT_EQ(side.normal, (Vec3{1, 0, 0}));
}

TEST(Mesh, ExactlyOnAnEdgeOrAVertexIsNoContactAndJustOutsideThemIsOutside) {
  const Model m = box_mesh_model();
  const Vec3 edge{0.010, 0.002, 0.010};    // between the top and the +x side
  const Vec3 vertex{0.010, 0.008, 0.010};  // top, +x and +y
  EXPECT_EQ(probe(m, 0, edge).depth_m, 0.0);
  EXPECT_EQ(probe(m, 0, vertex).depth_m, 0.0);
  // just outside them, nearest to the edge or the vertex
  EXPECT_EQ(probe(m, 0, edge + Vec3{1e-6, 0, 1e-7}).depth_m, 0.0);
  EXPECT_EQ(probe(m, 0, edge + Vec3{1e-7, 0, 1e-6}).depth_m, 0.0);
  EXPECT_EQ(probe(m, 0, vertex + Vec3{1e-6, 1e-7, 1e-7}).depth_m, 0.0);
  EXPECT_EQ(probe(m, 0, vertex + Vec3{-1e-7, 1e-6, -1e-7}).depth_m, 0.0);
  // just inside them: the nearer face pushes, at its depth
  const Probe near_edge = probe(m, 0, edge + Vec3{-2e-6, 0, -1e-6});
  EXPECT_NEAR(near_edge.depth_m, 1e-6, 1e-12);
  EXPECT_EQ(near_edge.normal, (Vec3{0, 0, 1}));
  const Probe near_vertex = probe(m, 0, vertex + Vec3{-3e-6, -1e-6, -2e-6});
  EXPECT_NEAR(near_vertex.depth_m, 1e-6, 1e-12);
  EXPECT_EQ(near_vertex.normal, (Vec3{0, 1, 0}));
}

TEST(Mesh, APointDeepInsideIsPushedOutThroughTheNearestFace) {
  const Model m = box_mesh_model();
  // the centre: 5 mm below the top and above the base, farther from the sides
  const Probe centre = probe(m, 0, kCentre + Vec3{0, 0, 0.0001});
  EXPECT_NEAR(centre.depth_m, 0.0049, 1e-12);
  EXPECT_EQ(centre.normal, (Vec3{0, 0, 1}));
  const Probe low = probe(m, 0, kCentre + Vec3{0.001, 0.0005, -0.0002});
  EXPECT_NEAR(low.depth_m, 0.0048, 1e-12);
  EXPECT_EQ(low.normal, (Vec3{0, 0, -1}));
}

TEST(Mesh, AThinWallPushesThroughItsNearerFace) {
  Model m;
  // a wall 1 mm thick across x, 20 mm long and tall
  models::add_mesh(m, "wall", models::box_mesh({0, 0, 0.01}, {0.0005, 0.01, 0.01}));
  for (double into_m : {1e-6, 0.0002, 0.0004}) {
    const Probe p = probe(m, 0, {-0.0005 + into_m, 0.001, 0.01});
    EXPECT_NEAR(p.depth_m, into_m, 1e-12);
    EXPECT_EQ(p.normal, (Vec3{-1, 0, 0})) << into_m;
  }
  // past the middle the far face is nearer (docs/physics.md: meshes keep no entry face)
  const Probe past = probe(m, 0, {0.0001, 0.001, 0.01});
  EXPECT_NEAR(past.depth_m, 0.0004, 1e-12);
  EXPECT_EQ(past.normal, (Vec3{1, 0, 0}));
}

// the largest jump of the contact force over a straight path through n points, less the
// stiffness times the step's travel (<= 0: continuous in the sense of the contact guarantees)
double worst_jump_n(const Model& m, int o, const Vec3& from, const Vec3& to, int n, int& in_contact) {
  double worst = -1.0;
  Vec3 last_force;
  in_contact = 0;
  for (int i = 0; i <= n; ++i) {
    const Probe p = probe(m, o, from + (to - from) * (static_cast<double>(i) / n));
    const Vec3 force = p.normal * (kStiffness_n_per_m * p.depth_m);
    in_contact += p.depth_m > 0.0;
    if (i > 0) worst = std::max(worst, norm(force - last_force) - kStiffness_n_per_m * norm(to - from) / n);
    last_force = force;
  }
  return worst;
}

TEST(Mesh, TheForceIsContinuousAcrossEdgesBetweenCoplanarAndConcaveFaces) {
  // a step: a plateau 6 mm high beside one 2 mm high, joined by a steep slope over one cell;
  // every cell's diagonal is an edge between coplanar triangles, and the slope's foot a
  // concave edge
  std::vector<double> heights;
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 6; ++c) heights.push_back(c < 3 ? 0.002 : 0.006);
  }
  Model m;
  models::add_mesh(m, "step", heightfield_mesh(heights, 5, 6, 0.004, {0, 0, 0}, -0.004));
  int touching = 0;
  // 0.5 mm below the low plateau, across the diagonals of its cells
  // (kept more than 0.5 mm inside the walls: across a convex edge the push switches faces)
  EXPECT_LE(worst_jump_n(m, 0, {-0.0092, -0.0072, 0.0015}, {-0.0025, 0.0072, 0.0015}, 4000, touching), 1e-9);
  EXPECT_EQ(touching, 4001);
  // inside, below the low plateau's level, from under it across the slope's foot to under the slope
  EXPECT_LE(worst_jump_n(m, 0, {-0.006, 0.001, 0.0012}, {0.0015, 0.0013, 0.0016}, 6000, touching), 1e-9);
  EXPECT_EQ(touching, 6001);
  // under a vertex of the foot, where the slope's triangles and the plateau's meet
  EXPECT_LE(worst_jump_n(m, 0, {-0.004, -0.002, 0.0013}, {0.0, 0.002, 0.0011}, 6000, touching), 1e-9);
  EXPECT_EQ(touching, 6001);
}

// a body of 4 x 4 masses and its centre against every object of `m`, 6000 N/m and 0.02 N s/m
Model with_body(Model m, Vec3 start) {
  m.set_rate(5000.0);
  models::add_body(m, start);
  for (int o = 0; o < static_cast<int>(m.objects.size()); ++o) {
    for (int i = 0; i < static_cast<int>(m.points.size()); ++i) models::add_contact(m, i, o, kStiffness_n_per_m, 0.02);
  }
  for (ContactPair& c : m.contacts) c.edge_skin_m = 0.001;
  return m;
}

TEST(Mesh, ABoxAsTwelveTrianglesGivesTheBoxObjectsForces) {
  Model as_box;
  models::add_boxes(as_box, "box", {{kCentre, kHalf}});
  as_box.index_boxes();
  as_box = with_body(as_box, {0, 0, 0.012});
  const Model as_mesh = with_body(box_mesh_model(), {0, 0, 0.012});
  State box = make_state(as_box), mesh = make_state(as_mesh);
  // over the whole top and off its sides, from 2 mm above it to 0.8 mm into it (less than the
  // edge skin: deeper, a box keeps its entry face where a mesh takes the nearest)
  models::Walk walk({-0.016, -0.014, 0.0092}, {0.016, 0.014, 0.012}, 17);
  double worst_n = 0.0;
  long touching = 0, sides = 0;
  for (long n = 0; n < 300000; ++n) {
    box.proxy_position_m[0] = mesh.proxy_position_m[0] = walk.next(as_box.dt_s);
    step(as_box, box);
    step(as_mesh, mesh);
    worst_n = std::max(worst_n, norm(box.proxy_force_n[0] - mesh.proxy_force_n[0]));
    for (const ContactState& c : mesh.contacts) {
      touching += c.active;
      sides += c.active && std::abs(c.normal.z) < 0.5;
    }
  }
  EXPECT_LE(worst_n, 1e-9);
  std::printf("%ld contact steps, %ld of them against a side; largest difference %.3g N\n", touching, sides, worst_n);
  EXPECT_GT(touching, 100000);
  EXPECT_GT(sides, 1000);
}

// the height field of the bench: bumps of 1 mm on a plateau 5 mm high, `cells` per side over 60 mm
Mesh bumps(int cells) { return reference::bumpy_field(cells, 0.06 / cells); }

TEST(Mesh, TheHeldTriangleAndCullingMatchTheFullSearchOfEveryPairEveryStep) {
  const Model m = with_body([] {
    Model b;
    models::add_mesh(b, "bumps", bumps(40));
    models::add_mesh(b, "box", models::box_mesh({0.04, 0, 0.005}, {0.005, 0.005, 0.005}));
    return b;
  }(), {0, 0, 0.008});
  State fast = make_state(m), full = make_state(m);
  full.hold = false;
  full.cull = false;
  models::Walk walk({-0.03, -0.02, 0.0045}, {0.05, 0.02, 0.009}, 23);
  long contact_steps = 0, held_steps = 0, ring_steps = 0;
  for (long n = 0; n < 200000; ++n) {
    fast.proxy_position_m[0] = full.proxy_position_m[0] = walk.next(m.dt_s);
    step(m, fast);
    step(m, full);
    ASSERT_TRUE(same_bits(fast.proxy_force_n[0], full.proxy_force_n[0])) << "step " << n;
    for (std::size_t k = 0; k < m.contacts.size(); ++k) {
      const ContactState &a = fast.contacts[k], &b = full.contacts[k];
      ASSERT_TRUE(a.active == b.active && same_bits(a.depth_m, b.depth_m) && same_bits(a.normal, b.normal)) << "step " << n << " pair " << k;
      contact_steps += a.active;
      const Vec3 moved = fast.x[m.contacts[k].point] - a.hold_at_m;
      held_steps += a.active && a.hold_r2 > 0.0 && dot(moved, moved) > 0.0;
      // the hold planned this step by the nearest of the last search's ring, not by a search
      const Vec3& x = fast.x[m.contacts[k].point];
      ring_steps += a.active && a.hold_at_m == x && !(a.ring_at_m == x);
    }
  }
  std::printf("%ld contact steps, %ld of them on a hold planned earlier, %ld from a ring\n", contact_steps, held_steps, ring_steps);
  EXPECT_GT(contact_steps, 100000);
  EXPECT_GT(held_steps, contact_steps / 3);
  EXPECT_GT(ring_steps, contact_steps / 100);
}

TEST(Mesh, TheStepAllocatesNothing) {
  const Model m = with_body([] {
    Model b;
    models::add_mesh(b, "bumps", bumps(100));
    return b;
  }(), {0, 0, 0.008});
  State s = make_state(m);
  models::Walk walk({-0.02, -0.02, 0.004}, {0.02, 0.02, 0.0065}, 29);
  long touching = 0;
  std::size_t allocations = 0;
  {
    enact::test::AllocGuard guard;
    for (int n = 0; n < 20000; ++n) {
      s.proxy_position_m[0] = walk.next(m.dt_s);
      step(m, s);
      touching += s.in_contact[m.proxies[0].first_body];
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(touching, 1000);
}

// what searches from points over the middle 50 mm of a field test, on average and at most, and
// the nearest distances they find (in order)
struct SearchWork {
  double nodes = 0.0;
  double triangles = 0.0;
  long most_nodes = 0;
  std::vector<double> distances_m;
};

SearchWork search_work(const Mesh& mesh) {
  SearchWork w;
  SearchCounts all;
  // 31 x 31 columns 1.7 mm apart (off the cells' lattice), from 1 mm above the plateau to
  // 2.5 mm into it: outside, on and under the bumps
  for (int i = 0; i < 31; ++i) {
    for (int j = 0; j < 31; ++j) {
      for (double z_m : {0.0060, 0.0052, 0.0046, 0.0040, 0.0025}) {
        SearchCounts one;
        w.distances_m.push_back(nearest(mesh, {-0.0255 + 0.0017 * i, -0.0255 + 0.0017 * j, z_m}, one).distance_m);
        w.most_nodes = std::max(w.most_nodes, one.nodes);
        all.nodes += one.nodes;
        all.triangles += one.triangles;
      }
    }
  }
  w.nodes = static_cast<double>(all.nodes) / static_cast<double>(w.distances_m.size());
  w.triangles = static_cast<double>(all.triangles) / static_cast<double>(w.distances_m.size());
  return w;
}

TEST(Mesh, ASearchTestsLogarithmicallyManyBoxesWhenTheTrianglesKeepTheirSize) {
  // the bench's fixed-cell fields: 15 mm cells, the 60 mm square grown from 96 to 101 120
  // triangles (2.4 m a side); near the points the same triangles, vertex for vertex
  const SearchWork first = search_work(reference::bumpy_field(4, 0.015, 0));
  const double per_log2 = first.nodes / std::log2(96.0);
  // 1.5: where the hierarchy's split planes fall near the points varies with the size (a point
  // near a split searches both sides); a search growing like sqrt(n) or n would exceed it
  const auto bound = [per_log2](double n) { return 1.5 * per_log2 * std::log2(n); };
  for (int margin : {6, 23, 77}) {
    const Mesh mesh = reference::bumpy_field(4 + 2 * margin, 0.015, margin);
    const double n = static_cast<double>(mesh.triangles.size());
    const SearchWork w = search_work(mesh);
    std::printf("%6.0f triangles: %.1f boxes a search on average (bound %.1f, at most %ld), %.1f triangles (%.1f at 96)\n", n, w.nodes,
                bound(n), w.most_nodes, w.triangles, first.triangles);
    EXPECT_LE(w.nodes, bound(n)) << n;
    // the triangles near the points are the same: as many tested
    EXPECT_LE(w.triangles, 1.5 * first.triangles) << n;
    // and the same nearest points: the field only grew away from them
    ASSERT_EQ(w.distances_m.size(), first.distances_m.size());
    for (std::size_t k = 0; k < w.distances_m.size(); ++k) ASSERT_NEAR(w.distances_m[k], first.distances_m[k], 1e-12) << n << " query " << k;
  }
  // the bound at 10^5 triangles is below what a search growing like sqrt(n) would test
  EXPECT_LT(bound(101120.0), first.nodes * std::sqrt(101120.0 / 96.0));
}

TEST(Mesh, PairCullingSkipsTheMeshOnlyAwayFromItsBounds) {
  Model m = box_mesh_model();
  EXPECT_TRUE(apart(m, m.objects[0], {0, 0, 0.0161}, 0.006));
  EXPECT_FALSE(apart(m, m.objects[0], {0, 0, 0.0159}, 0.006));
  EXPECT_FALSE(apart(m, m.objects[0], kCentre, 0.001));
  EXPECT_TRUE(apart(m, m.objects[0], {0.02, 0.02, 0.005}, 0.009));
}

}  // namespace
}  // namespace enact::physics
