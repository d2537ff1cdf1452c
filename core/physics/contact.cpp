#include "core/physics/contact.h"

#include <algorithm>
#include <bit>
#include <limits>

namespace enact::physics {
namespace {

// tolerance for "on a face" and "strictly inside another box" (m)
constexpr double kTolerance_m = 1e-9;
// a face whose normal is within 120 degrees of the entry face's may push (not the opposite face)
constexpr double kOppositeCos = -0.5;
// faces whose normals are this close to the entry face's continue it (coplanar tops of a union)
constexpr double kParallelCos = 0.999;
// the near-box cache of a contact holds while the point stays this close to where it was made
constexpr double kNearMargin_m = 0.002;
using math::kInfinity;
// a parallel face of another box this close to the pushing face's depth (in hold distance) is a
// tie, checked each step, rather than a bound on the hold (coplanar tops of a union: 0)
constexpr double kTieBand_m = 1e-5;
// taken off every hold distance: far above the rounding of depths at workspace scale (m)
constexpr double kHoldTolerance_m = 1e-10;
// the most triangles a ring may have for a mesh contact to test them all before searching
constexpr int kMaxRing = 32;

double sign_of(int face) { return face % 2 == 0 ? 1.0 : -1.0; }
Vec3 face_normal(const Box& box, int face) { return box.rotation.column(face / 2) * sign_of(face); }

// x in box coordinates, one axis at a time (most boxes are rejected after one or two dot
// products); false when x is not inside the box grown by margin_m
bool local_coordinates(const Box& box, const Vec3& x, double local[3], double margin_m = 0.0) {
  const Vec3 d = x - box.center_m;
  local[1] = dot(box.rotation.c1, d);
  if (std::abs(local[1]) >= box.half_extents_m.y + margin_m) return false;
  local[0] = dot(box.rotation.c0, d);
  if (std::abs(local[0]) >= box.half_extents_m.x + margin_m) return false;
  local[2] = dot(box.rotation.c2, d);
  return std::abs(local[2]) < box.half_extents_m.z + margin_m;
}

bool inside_box(const Box& box, const Vec3& x, double margin_m) {
  double local[3];
  return local_coordinates(box, x, local, margin_m);
}

// depth of a point (box coordinates) below face 0..5 (+x, -x, +y, -y, +z, -z): positive inside
double depth_below(const Box& box, const double local[3], int face) {
  return component(box.half_extents_m, face / 2) - sign_of(face) * local[face / 2];
}

// the boxes of `object` selected by `mask`, as indices into Model::boxes (objects of more
// than 64 boxes are not cached: all of them)
bool selected(const Object& object, std::uint64_t mask, int box) {
  const int k = box - object.first_box;
  return k >= 64 || ((mask >> k) & 1u);
}
constexpr std::uint64_t kAllBoxes = ~std::uint64_t{0};

// a point x on a face (outward normal n) is exposed unless another box of the same union holds
// the point just outside it: a box standing flush on the face (a wall on a slab) covers it
bool exposed(const Model& model, const Object& object, int face_box, const Vec3& x, const Vec3& n) {
  const Vec3 outside = x + n * kTolerance_m;
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    if (i != face_box && inside_box(model.boxes[i], outside, 0.0)) return false;
  }
  return true;
}

// the exposed face the segment x_prev -> x crossed first, among the boxes containing x
bool crossed_face(const Model& model, const Object& object, std::uint64_t near, const Vec3& x_prev, const Vec3& x,
                  Vec3& normal) {
  double best_t = kInfinity;
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    const Box& box = model.boxes[i];
    double now[3];
    if (!selected(object, near, i) || !local_coordinates(box, x, now)) continue;
    const Vec3 b = box.rotation.transpose_times(x_prev - box.center_m);
    const double before[3] = {b.x, b.y, b.z};
    for (int face = 0; face < 6; ++face) {
      const double d_before = -depth_below(box, before, face);
      const double d_now = -depth_below(box, now, face);
      if (d_before < 0.0 || d_now >= 0.0) continue;
      const double t = d_before / (d_before - d_now);
      if (t >= best_t) continue;
      // the crossing point must lie on the face rectangle and on the union's surface
      double hit[3];
      bool on_face = true;
      for (int axis = 0; axis < 3; ++axis) {
        hit[axis] = before[axis] + (now[axis] - before[axis]) * t;
        on_face = on_face && (axis == face / 2 || std::abs(hit[axis]) <= component(box.half_extents_m, axis) + kTolerance_m);
      }
      const Vec3 n = face_normal(box, face);
      if (!on_face || !exposed(model, object, i, box.rotation * Vec3{hit[0], hit[1], hit[2]} + box.center_m, n)) continue;
      best_t = t;
      normal = n;
    }
  }
  return best_t < kInfinity;
}

// the best face found so far in a category
struct Pick {
  double depth_m = kInfinity;
  int box = -1;
  int face = -1;
  bool found() const { return box >= 0; }
};

// over the boxes containing x: the shallowest face within `skin_m` (edge) and the shallowest
// face parallel to `entry` no deeper than `parallel_max_m` (parallel), never the face opposite
// `entry`; covered faces are skipped when `exposed_only`. false when x is in no box.
bool pick_faces(const Model& model, const Object& object, std::uint64_t near, const Vec3& x, const Vec3& entry,
                double skin_m, double parallel_max_m, bool exposed_only, Pick& edge, Pick& parallel) {
  bool in_any = false;
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    const Box& box = model.boxes[i];
    double local[3];
    if (!selected(object, near, i) || !local_coordinates(box, x, local)) continue;
    in_any = true;
    const Vec3 e = box.rotation.transpose_times(entry);  // the entry normal in box axes
    for (int face = 0; face < 6; ++face) {
      const double along = sign_of(face) * component(e, face / 2);
      if (!((box.faces >> face) & 1u) || along < kOppositeCos) continue;
      const double depth = depth_below(box, local, face);
      const bool to_edge = depth <= skin_m && depth < edge.depth_m;
      const bool to_parallel = along > kParallelCos && depth < parallel.depth_m && depth <= parallel_max_m;
      if (!to_edge && !to_parallel) continue;
      const Vec3 n = face_normal(box, face);
      if (exposed_only && !((box.exposed >> face) & 1u) && !exposed(model, object, i, x + n * depth, n)) continue;
      if (to_edge) edge = {depth, i, face};
      if (to_parallel) parallel = {depth, i, face};
    }
  }
  return in_any;
}

// x in box coordinates, all three; false when x is not inside the box
bool all_coordinates(const Box& box, const Vec3& x, double local[3]) {
  const Vec3 l = box.rotation.transpose_times(x - box.center_m);
  local[0] = l.x;
  local[1] = l.y;
  local[2] = l.z;
  const Vec3& h = box.half_extents_m;
  return std::abs(l.x) < h.x && std::abs(l.y) < h.y && std::abs(l.z) < h.z;
}

// the face that pushed last step, extended beyond its box: a point that left the box still
// below the face's plane (pushed into a concave corner, out of a wall's box into the slab it
// stands on) is pushed on out through it when that is the shallowest parallel face, by more
// than the tolerance (coplanar faces of the boxes it is in keep pushing)
void extend_held(const Model& model, const ContactState& held, const Vec3& x, Pick& parallel) {
  double local[3];
  if (all_coordinates(model.boxes[held.box], x, local)) return;  // in its box: already picked
  const double depth = depth_below(model.boxes[held.box], local, held.face);
  if (depth > 0.0 && depth < parallel.depth_m - kTolerance_m) parallel = {depth, held.box, held.face};
}

// the faces of the near boxes the point is just outside of (within the skin), extended: a
// point pressed into a slab's top that slides under the foot of a wall standing on it (the
// slab's top covered, no face continuing it) is pushed back out through the wall's face
// less than the skin above it, not on through the slab's far end
void extend_near(const Model& model, const Object& object, std::uint64_t near, const Vec3& x, const Vec3& entry,
                 double skin_m, Pick& chosen) {
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    const Box& box = model.boxes[i];
    double local[3];
    if (!selected(object, near, i) || all_coordinates(box, x, local) || !inside_box(box, x, skin_m)) continue;
    const Vec3 e = box.rotation.transpose_times(entry);
    for (int face = 0; face < 6; ++face) {
      const double depth = depth_below(box, local, face);
      const bool pushes = ((box.faces >> face) & 1u) && sign_of(face) * component(e, face / 2) >= kOppositeCos;
      if (pushes && depth > 0.0 && depth <= skin_m && depth < chosen.depth_m) chosen = {depth, i, face};
    }
  }
}

// the face that pushes a point at x out of a union of boxes, given the normal of the face it
// entered through (zero: none). It keeps pushing out through faces parallel to the entry face
// (among them the face that pushed last step, extended beyond its box);
// another face takes over only when the point is less than `skin_m` below it and shallower
// (riding over an edge); a parallel face continues the entry face only within the skin below
// `depth_m` (the depth the point had plus its move): a parallel face farther in is another
// surface (the far end of a box joined at an angle, which would push the point on through);
// the face opposite the entry face never pushes, and a face covered by another box of the
// union only when nothing else is left. false when x is in no box.
bool choose_face(const Model& model, const Object& object, std::uint64_t near, const Vec3& x, const Vec3& entry,
                 double skin_m, double depth_m, ContactState& contact) {
  Pick edge, parallel;
  if (!pick_faces(model, object, near, x, entry, skin_m, depth_m + skin_m, true, edge, parallel)) return false;
  if (contact.active && contact.box >= 0) extend_held(model, contact, x, parallel);
  Pick chosen = edge.found() && (!parallel.found() || edge.depth_m < parallel.depth_m) ? edge : parallel;
  // rarely: no face continues the entry face; then the shallowest face just outside which the
  // point is, else the shallowest exposed face, else any face
  Pick unused;
  if (!chosen.found()) extend_near(model, object, near, x, entry, skin_m, chosen);
  if (!chosen.found()) pick_faces(model, object, near, x, entry, kInfinity, kInfinity, true, chosen, unused);
  if (!chosen.found()) pick_faces(model, object, near, x, entry, kInfinity, kInfinity, false, chosen, unused);
  contact.normal = chosen.found() ? face_normal(model.boxes[chosen.box], chosen.face) : entry;
  contact.depth_m = chosen.found() ? chosen.depth_m : 0.0;
  contact.box = chosen.box;
  contact.face = chosen.face;
  return true;
}

// would a face of `box` (containing the point at `local`) take over from a face `own_m` deep
// with outward normal `normal`? choose_face's rule: within the skin or parallel, shallower,
// never the opposite face
bool competes(const Box& box, const double local[3], const Vec3& normal, double own_m, double skin_m) {
  const Vec3 e = box.rotation.transpose_times(normal);
  for (int face = 0; face < 6; ++face) {
    const double along = sign_of(face) * component(e, face / 2);
    const double depth = depth_below(box, local, face);
    if (((box.faces >> face) & 1u) && along >= kOppositeCos && (depth <= skin_m || along > kParallelCos) && depth < own_m) return true;
  }
  return false;
}

// how far the point at `local` (in `box`, not the box of the pushing face) can move before a
// face of the box could take over from the face `own_m` deep with outward normal `normal`
// (competes' rule): outside the box with that margin, or every face deep enough. Coplanar
// faces (parallel, within kTieBand_m of the pushing one) are left to a tie of the contact while
// one is free: checked exactly each step, they do not bound the distance
double takeover_distance(const Box& box, int index, const double local[3], const Vec3& normal, double own_m, double skin_m,
                         ContactState& contact) {
  double outside = -kInfinity;
  for (int axis = 0; axis < 3; ++axis) outside = std::max(outside, std::abs(local[axis]) - component(box.half_extents_m, axis));
  const Vec3 e = box.rotation.transpose_times(normal);
  double faces = kInfinity;
  for (int face = 0; face < 6; ++face) {
    const double along = sign_of(face) * component(e, face / 2);
    if (!((box.faces >> face) & 1u) || along < kOppositeCos) continue;
    const double depth = depth_below(box, local, face);
    const bool parallel = along > kParallelCos;
    const double margin = std::max(parallel ? -kInfinity : depth - skin_m, 0.5 * (depth - own_m));
    if (parallel && margin < kTieBand_m) {
      auto free = std::find_if(std::begin(contact.ties), std::end(contact.ties), [](const ContactState::Tie& t) { return t.box < 0; });
      if (free != std::end(contact.ties)) {
        *free = {index, face};
        continue;
      }
    }
    faces = std::min(faces, margin);
  }
  return std::max(outside, faces);
}

// the common case: the point is still inside the box of the face that pushed it last step,
// that face is always exposed, and no face of any box containing the point would take over;
// then that face still pushes (choose_face would pick it). With `plan`, also plans the
// contact's hold (held): how far the point can move while all of this stays true, each
// distance bounding a depth that moves at most as far as the point. false: take the general path.
bool same_face(const Model& model, const Object& object, std::uint64_t near, const Vec3& x, double skin_m, bool plan,
               ContactState& contact) {
  contact.hold_r2 = 0.0;
  const Box& own_box = model.boxes[contact.box];
  if (!((own_box.exposed >> contact.face) & 1u)) return false;
  // depths below the six faces of the own box, straight from its axes
  const Vec3 d = x - own_box.center_m;
  const double lx = dot(own_box.rotation.c0, d), ly = dot(own_box.rotation.c1, d), lz = dot(own_box.rotation.c2, d);
  const Vec3& h = own_box.half_extents_m;
  const double depth[6] = {h.x - lx, h.x + lx, h.y - ly, h.y + ly, h.z - lz, h.z + lz};
  const double own = depth[contact.face];
  // left the box
  const double inside = std::min(std::min(std::min(depth[0], depth[1]), std::min(depth[2], depth[3])), std::min(depth[4], depth[5]));
  if (inside <= 0.0) return false;
  // in its own box the other faces are perpendicular or opposite: they take over only within
  // the skin, and one does when the shallowest of them does (a face that cannot push counts
  // as infinitely deep)
  const unsigned side_faces = own_box.faces & ~(3u << (contact.face & ~1));
  double side = kInfinity;
  for (int face = 0; face < 6; ++face) side = std::min(side, (side_faces >> face) & 1u ? depth[face] : kInfinity);
  if (side <= skin_m && side < own) return false;
  double radius = std::min(inside, std::max(side - skin_m, 0.5 * (side - own)));
  // the other boxes of the object the point may be in (the near ones, bit by bit); outside
  // the near boxes' margin others could be too
  std::fill(std::begin(contact.ties), std::end(contact.ties), ContactState::Tie{});
  auto taken_over = [&](int i) {
    const Box& box = model.boxes[i];
    if (!plan) {
      double local[3];
      return local_coordinates(box, x, local) && competes(box, local, contact.normal, own, skin_m);
    }
    double local[3];
    if (all_coordinates(box, x, local) && competes(box, local, contact.normal, own, skin_m)) return true;
    radius = std::min(radius, takeover_distance(box, i, local, contact.normal, own, skin_m, contact));
    return false;
  };
  if (object.box_count > 64) {
    for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
      if (i != contact.box && taken_over(i)) return false;
    }
  } else {
    for (std::uint64_t rest = near & ~(std::uint64_t{1} << (contact.box - object.first_box)); rest != 0; rest &= rest - 1) {
      if (taken_over(object.first_box + std::countr_zero(rest))) return false;
    }
    if (plan) radius = std::min(radius, kNearMargin_m - norm(x - contact.near_at_m));
  }
  contact.depth_m = own;
  radius -= kHoldTolerance_m;
  if (plan && radius > 0.0) {
    contact.hold_at_m = x;
    contact.hold_r2 = radius * radius;
  }
  return true;
}

// the held face (same_face's plan): the point is within the hold's distance and no tie has
// become shallower; then that face still pushes, at the depth same_face would compute
bool held(const Model& model, const Vec3& x, ContactState& contact) {
  const Vec3 moved = x - contact.hold_at_m;
  if (!(dot(moved, moved) < contact.hold_r2)) return false;
  // the pushing face's axis alone, as same_face computes it (depth_below's sum, unrolled: this
  // is the step's hot path)
  const Box& box = model.boxes[contact.box];
  const int axis = contact.face / 2;
  const double l = dot(box.rotation.column(axis), x - box.center_m);
  const double own = contact.face % 2 == 0 ? component(box.half_extents_m, axis) - l : component(box.half_extents_m, axis) + l;
  for (const ContactState::Tie& tie : contact.ties) {
    double local[3];
    if (tie.box >= 0 && local_coordinates(model.boxes[tie.box], x, local) && depth_below(model.boxes[tie.box], local, tie.face) < own) return false;
  }
  contact.depth_m = own;
  return true;
}

// the boxes the point can be inside or within the skin of (extend_near): cached per contact,
// refreshed when it moved too far. With the skin in the margin the cache never changes a
// result, only how many boxes are tried: which steps refresh it does not matter
std::uint64_t near_boxes(const Model& model, const Object& object, const Vec3& x, double skin_m, ContactState& contact) {
  if (object.box_count > 64) return kAllBoxes;
  const Vec3 moved = x - contact.near_at_m;
  if (contact.near_valid && dot(moved, moved) < kNearMargin_m * kNearMargin_m) return contact.near_boxes;
  contact.near_boxes = 0;
  for (int k = 0; k < object.box_count; ++k) {
    if (inside_box(model.boxes[object.first_box + k], x, kNearMargin_m + skin_m)) contact.near_boxes |= std::uint64_t{1} << k;
  }
  contact.near_at_m = x;
  contact.near_valid = true;
  return contact.near_boxes;
}

bool inside_near(const Model& model, const Object& object, std::uint64_t near, const Vec3& x) {
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    if (selected(object, near, i) && inside_box(model.boxes[i], x, 0.0)) return true;
  }
  return false;
}

// a box strictly below a plane somewhere (some corner under the surface)
bool box_under_plane(const Box& box, const Object& plane) {
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 local{(corner & 1 ? 1 : -1) * box.half_extents_m.x, (corner & 2 ? 1 : -1) * box.half_extents_m.y,
                     (corner & 4 ? 1 : -1) * box.half_extents_m.z};
    if (dot(plane.plane_normal, box.rotation * local + box.center_m - plane.plane_point_m) < -kTolerance_m) return true;
  }
  return false;
}

// how far a box reaches along a unit direction from the origin
double reach_along(const Box& box, const Vec3& n) {
  double r = dot(n, box.center_m);
  for (int k = 0; k < 3; ++k) r += std::abs(dot(n, box.rotation.column(k))) * component(box.half_extents_m, k);
  return r;
}

// separating-axis test on the world axes only: conservative (may say yes for disjoint boxes)
bool boxes_may_overlap(const Box& a, const Box& b) {
  for (const Vec3& n : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
    if (reach_along(a, n) <= -reach_along(b, -n) + kTolerance_m || reach_along(b, n) <= -reach_along(a, -n) + kTolerance_m) return false;
  }
  return true;
}

// a contact pushed out of a solid through its nearest surface point, `depth_m` below it along
// `normal`; 0 (no contact) when the point is not inside
double push_out(double depth_m, const Vec3& normal, ContactState& contact) {
  contact.active = depth_m > 0.0;
  contact.depth_m = contact.active ? depth_m : 0.0;
  if (contact.active) contact.normal = contact.entry_normal = normal;
  return contact.depth_m;
}

// a point against a mesh at its nearest point (on one triangle): inside when it is behind the
// pseudo-normal there; pushed out along the face normal, or straight to the nearest point on
// an edge or a vertex (inside a concave edge)
double push_from(const Mesh& mesh, const MeshHit& hit, const Vec3& x, ContactState& contact) {
  const bool inside = dot(x - hit.closest_m, hit.pseudo_normal) < 0.0;
  if (!inside || !(hit.distance_m > 0.0)) return push_out(0.0, Vec3{}, contact);
  const Vec3 normal = hit.on_face ? mesh.triangles[hit.triangle].normal : (hit.closest_m - x) * (1.0 / hit.distance_m);
  return push_out(hit.distance_m, normal, contact);
}

// the nearest triangle of the last search's ring, when it is provably the nearest of all (the
// search would find it): nearer than every other of the ring by the tolerance, and than every
// triangle outside the ring can be (its distance then less the point's travel since)
bool ring_nearest(const Mesh& mesh, const Vec3& x, const ContactState& contact, MeshHit& hit) {
  const double others_m = contact.ring_bound_m - norm(x - contact.ring_at_m) - kHoldTolerance_m;
  if (contact.ring_of < 0 || !(others_m > 0.0)) return false;
  hit.distance_m = kInfinity;
  double second_m = kInfinity;
  for (int k = mesh.ring_first[contact.ring_of]; k < mesh.ring_first[contact.ring_of + 1]; ++k) {
    const MeshHit h = nearest_on(mesh, mesh.ring[k], x);
    if (h.distance_m < hit.distance_m) {
      second_m = hit.distance_m;
      hit = h;
    } else {
      second_m = std::min(second_m, h.distance_m);
    }
  }
  hit.runner_up_m = std::min(second_m, others_m);
  return hit.distance_m < hit.runner_up_m - kHoldTolerance_m;
}

// the nearest triangle through the hierarchy; with the hold, also how far the nearest triangle
// outside its ring is, for ring_nearest (not for rings larger than kMaxRing: testing them all
// would cost more than a search)
MeshHit search_mesh(const Mesh& mesh, const Vec3& x, ContactState& contact, bool hold) {
  const MeshHit hit = nearest(mesh, x);
  contact.ring_of = -1;
  contact.ring_at_m = x;
  if (!hold || mesh.ring_first[hit.triangle + 1] - mesh.ring_first[hit.triangle] > kMaxRing) return hit;
  contact.ring_of = hit.triangle;
  contact.ring_bound_m = nearest_beyond(mesh, hit.triangle, x);
  return hit;
}

// a point against a mesh: the held triangle while the point stays within its hold, else the
// nearest of the last search's ring while it provably is the nearest, else the nearest through
// the hierarchy (the first two are what the search would find)
double mesh_contact(const Mesh& mesh, const Vec3& x, ContactState& contact, bool hold) {
  const Vec3 moved = x - contact.hold_at_m;
  if (hold && contact.triangle >= 0 && dot(moved, moved) < contact.hold_r2) {
    if (!contact.active) return 0.0;
    const double depth = push_from(mesh, nearest_on(mesh, contact.triangle, x), x, contact);
    if (!contact.active) contact.hold_r2 = 0.0;  // left through it: no outside hold is planned
    return depth;
  }
  MeshHit hit;
  if (!hold || !ring_nearest(mesh, x, contact, hit)) hit = search_mesh(mesh, x, contact, hold);
  const double depth = push_from(mesh, hit, x, contact);
  // outside, the surface is hit.distance_m away; inside, every other triangle is farther than
  // the runner-up and the point's distances change at most as fast as it moves
  const double radius = (contact.active ? 0.5 * (hit.runner_up_m - hit.distance_m) : hit.distance_m) - kHoldTolerance_m;
  contact.triangle = hit.triangle;
  contact.hold_at_m = x;
  contact.hold_r2 = radius > 0.0 ? radius * radius : 0.0;
  return depth;
}

// the nearest point of a capsule's axis to x
Vec3 on_axis(const Object& capsule, const Vec3& x) {
  const Vec3 axis = capsule.axis_to_m - capsule.axis_from_m;
  const double length2 = dot(axis, axis);
  const double t = length2 > 0.0 ? std::clamp(dot(x - capsule.axis_from_m, axis) / length2, 0.0, 1.0) : 0.0;
  return capsule.axis_from_m + axis * t;
}

// a point against a capsule (or a sphere): pushed straight away from its axis
double capsule_contact(const Object& capsule, const Vec3& x, ContactState& contact) {
  const Vec3 out = x - on_axis(capsule, x);
  const double r = norm(out);
  return push_out(capsule.radius_m - r, r > 0.0 ? out * (1.0 / r) : capsule.axis_normal, contact);
}

// an axis-aligned box around an object that is not a plane
void bounds(const Model& m, const Object& o, Vec3& low, Vec3& high) {
  if (o.type == ObjectType::mesh) {
    low = m.meshes[o.mesh].nodes[0].low_m;
    high = m.meshes[o.mesh].nodes[0].high_m;
    return;
  }
  if (o.type == ObjectType::capsule) {
    const Vec3 r{o.radius_m, o.radius_m, o.radius_m};
    low = Vec3{std::min(o.axis_from_m.x, o.axis_to_m.x), std::min(o.axis_from_m.y, o.axis_to_m.y), std::min(o.axis_from_m.z, o.axis_to_m.z)} - r;
    high = Vec3{std::max(o.axis_from_m.x, o.axis_to_m.x), std::max(o.axis_from_m.y, o.axis_to_m.y), std::max(o.axis_from_m.z, o.axis_to_m.z)} + r;
    return;
  }
  // a union of boxes: how far its boxes reach along each world axis, both ways
  double lo[3], hi[3];
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 e{axis == 0 ? 1.0 : 0.0, axis == 1 ? 1.0 : 0.0, axis == 2 ? 1.0 : 0.0};
    lo[axis] = kInfinity;
    hi[axis] = -kInfinity;
    for (int i = o.first_box; i < o.first_box + o.box_count; ++i) {
      lo[axis] = std::min(lo[axis], -reach_along(m.boxes[i], -e));
      hi[axis] = std::max(hi[axis], reach_along(m.boxes[i], e));
    }
  }
  low = {lo[0], lo[1], lo[2]};
  high = {hi[0], hi[1], hi[2]};
}

// objects_overlap for meshes and capsules: their bounding boxes (a plane: some corner below it)
bool bounds_overlap(const Model& m, const Object& a, const Object& b) {
  if (a.type == ObjectType::plane && b.type == ObjectType::plane) return true;
  if (b.type == ObjectType::plane) return bounds_overlap(m, b, a);
  Vec3 low_b, high_b;
  bounds(m, b, low_b, high_b);
  if (a.type == ObjectType::plane) {
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 p{corner & 1 ? high_b.x : low_b.x, corner & 2 ? high_b.y : low_b.y, corner & 4 ? high_b.z : low_b.z};
      if (dot(a.plane_normal, p - a.plane_point_m) < -kTolerance_m) return true;
    }
    return false;
  }
  Vec3 low_a, high_a;
  bounds(m, a, low_a, high_a);
  return low_a.x < high_b.x && low_b.x < high_a.x && low_a.y < high_b.y && low_b.y < high_a.y && low_a.z < high_b.z && low_b.z < high_a.z;
}

}  // namespace

void Model::index_boxes() {
  for (const Object& o : objects) {
    for (int i = o.first_box; i < o.first_box + o.box_count; ++i) {
      Box& box = boxes[i];
      box.exposed = 0;
      for (int face = 0; face < 6; ++face) {
        // exposed when every other box lies behind the face's plane
        const Vec3 n = face_normal(box, face);
        const double plane = dot(n, box.center_m) + component(box.half_extents_m, face / 2);
        bool behind = true;
        for (int j = o.first_box; j < o.first_box + o.box_count; ++j) {
          behind = behind && (j == i || reach_along(boxes[j], n) <= plane + kTolerance_m);
        }
        if (behind) box.exposed |= static_cast<std::uint8_t>(1u << face);
      }
    }
  }
}

bool apart(const Model& model, const Object& object, const Vec3& centre_m, double radius_m) {
  if (object.type == ObjectType::plane) return dot(object.plane_normal, centre_m - object.plane_point_m) > radius_m;
  if (object.type == ObjectType::mesh) return distance_to_bounds(model.meshes[object.mesh], centre_m) > radius_m;
  if (object.type == ObjectType::capsule) return norm(centre_m - on_axis(object, centre_m)) > object.radius_m + radius_m;
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    const Box& box = model.boxes[i];
    const Vec3 local = box.rotation.transpose_times(centre_m - box.center_m);
    const Vec3& h = box.half_extents_m;
    if (std::abs(local.x) < h.x + radius_m && std::abs(local.y) < h.y + radius_m && std::abs(local.z) < h.z + radius_m) return false;
  }
  return true;
}

bool objects_overlap(const Model& m, const Object& a, const Object& b) {
  const auto bounded = [](const Object& o) { return o.type == ObjectType::mesh || o.type == ObjectType::capsule; };
  if (bounded(a) || bounded(b)) return bounds_overlap(m, a, b);
  if (a.type == ObjectType::plane && b.type == ObjectType::plane) return true;
  if (a.type == ObjectType::plane || b.type == ObjectType::plane) {
    const Object& plane = a.type == ObjectType::plane ? a : b;
    const Object& boxes = a.type == ObjectType::plane ? b : a;
    for (int i = boxes.first_box; i < boxes.first_box + boxes.box_count; ++i) {
      if (box_under_plane(m.boxes[i], plane)) return true;
    }
    return false;
  }
  for (int i = a.first_box; i < a.first_box + a.box_count; ++i) {
    for (int j = b.first_box; j < b.first_box + b.box_count; ++j) {
      if (boxes_may_overlap(m.boxes[i], m.boxes[j])) return true;
    }
  }
  return false;
}

double update_contact(const Model& model, const Object& object, const Vec3& x_prev, const Vec3& x, double skin_m,
                      ContactState& contact, bool hold) {
  if (object.type == ObjectType::mesh) return mesh_contact(model.meshes[object.mesh], x, contact, hold);
  if (object.type == ObjectType::capsule) return capsule_contact(object, x, contact);
  if (object.type == ObjectType::plane) {
    const double depth = dot(object.plane_normal, object.plane_point_m - x);
    contact.active = depth > 0.0;
    contact.depth_m = contact.active ? depth : 0.0;
    if (contact.active) contact.normal = contact.entry_normal = object.plane_normal;
    return contact.depth_m;
  }
  if (hold && contact.active && contact.box >= 0 && contact.hold_r2 > 0.0 && held(model, x, contact)) return contact.depth_m;
  const std::uint64_t near = near_boxes(model, object, x, skin_m, contact);
  if (contact.active && contact.box >= 0 && same_face(model, object, near, x, skin_m, hold, contact)) return contact.depth_m;
  contact.hold_r2 = 0.0;
  if (!contact.active) {
    // a new contact remembers the face it came through (or, starting inside, the shallowest)
    if (!inside_near(model, object, near, x)) return 0.0;
    if (!crossed_face(model, object, near, x_prev, x, contact.entry_normal)) {
      choose_face(model, object, near, x, Vec3{}, kInfinity, kInfinity, contact);
      contact.entry_normal = contact.normal;
    }
  }
  // a new contact: its entry face at any depth; a held one: no deeper than it was plus how far
  // the point moved (and the skin)
  const double depth_m = contact.active ? contact.depth_m + norm(x - x_prev) : kInfinity;
  contact.active = choose_face(model, object, near, x, contact.entry_normal, skin_m, depth_m, contact) && contact.depth_m > 0.0;
  // riding over an edge moves the contact to the new face
  if (contact.active) contact.entry_normal = contact.normal;
  else contact.depth_m = 0.0;
  return contact.depth_m;
}

}  // namespace enact::physics
