#include "core/physics/contact.h"

#include <limits>

namespace enact::physics {
namespace {

// tolerance for "on a face" and "strictly inside another box" (m)
constexpr double kTolerance_m = 1e-9;
// a face whose normal is within 120 degrees of the entry face's may push (not the opposite face)
constexpr double kOppositeCos = -0.5;
// faces whose normals are this close to the entry face's continue it (coplanar tops of a union)
constexpr double kParallelCos = 0.999;

double component(const Vec3& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }

// signed distance from a point in box coordinates to the plane of face 0..5 (+x, -x, +y, -y, +z, -z):
// positive outside
double face_distance(const Box& box, const Vec3& local, int face) {
  const int axis = face / 2;
  const double sign = face % 2 == 0 ? 1.0 : -1.0;
  return sign * component(local, axis) - component(box.half_extents_m, axis);
}

Vec3 face_normal(const Box& box, int face) { return box.rotation.column(face / 2) * (face % 2 == 0 ? 1.0 : -1.0); }

Vec3 to_local(const Box& box, const Vec3& x) { return box.rotation.transpose_times(x - box.center_m); }

bool inside_local(const Box& box, const Vec3& p, double margin_m) {
  const Vec3& h = box.half_extents_m;
  return std::abs(p.x) < h.x - margin_m && std::abs(p.y) < h.y - margin_m && std::abs(p.z) < h.z - margin_m;
}

bool inside_box(const Box& box, const Vec3& x, double margin_m) { return inside_local(box, to_local(box, x), margin_m); }

// a point on a face is exposed unless another box of the same union covers it
bool exposed(const Model& model, const Object& object, int face_box, const Vec3& x) {
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    if (i != face_box && inside_box(model.boxes[i], x, kTolerance_m)) return false;
  }
  return true;
}

// the exposed face the segment x_prev -> x crossed first, among the boxes containing x
bool crossed_face(const Model& model, const Object& object, const Vec3& x_prev, const Vec3& x, Vec3& normal) {
  double best_t = std::numeric_limits<double>::infinity();
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    const Box& box = model.boxes[i];
    const Vec3 now = to_local(box, x);
    if (!inside_local(box, now, 0.0)) continue;
    const Vec3 before = to_local(box, x_prev);
    for (int face = 0; face < 6; ++face) {
      const double d_before = face_distance(box, before, face);
      const double d_now = face_distance(box, now, face);
      if (d_before < 0.0 || d_now >= 0.0) continue;
      const double t = d_before / (d_before - d_now);
      if (t >= best_t) continue;
      // the crossing point must lie on the face rectangle and on the union's surface
      const Vec3 hit = before + (now - before) * t;
      bool on_face = true;
      for (int other = 0; other < 3; ++other) {
        on_face = on_face && (other == face / 2 || std::abs(component(hit, other)) <= component(box.half_extents_m, other) + kTolerance_m);
      }
      if (!on_face || !exposed(model, object, i, box.rotation * hit + box.center_m)) continue;
      best_t = t;
      normal = face_normal(box, face);
    }
  }
  return best_t < std::numeric_limits<double>::infinity();
}

// a face's candidacy: its depth, normal, and whether it is exposed (computed on demand)
struct Best {
  double depth_m = std::numeric_limits<double>::infinity();
  Vec3 normal;
  bool found() const { return depth_m < std::numeric_limits<double>::infinity(); }
  void take(double depth_m_, const Vec3& normal_) {
    depth_m = depth_m_;
    normal = normal_;
  }
};

// the face that pushes a point at x out of a union of boxes, given the normal of the face it
// entered through (zero: none). It keeps pushing out through faces parallel to the entry face;
// another face takes over only when the point is less than `skin_m` below it and shallower
// (riding over an edge); the face opposite the entry face never pushes, and a face covered by
// another box of the union only when nothing else is left. false when x is in no box.
bool choose_face(const Model& model, const Object& object, const Vec3& x, const Vec3& entry, double skin_m,
                 ContactState& contact) {
  Best parallel, edge, any, covered;
  bool in_any = false;
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    const Box& box = model.boxes[i];
    const Vec3 local = to_local(box, x);
    if (!inside_local(box, local, 0.0)) continue;
    in_any = true;
    for (int face = 0; face < 6; ++face) {
      if (!((box.faces >> face) & 1u)) continue;
      const Vec3 normal = face_normal(box, face);
      const double along = dot(normal, entry);
      if (along < kOppositeCos) continue;
      const double depth = -face_distance(box, local, face);
      const bool is_parallel = along > kParallelCos;
      const bool wins = (is_parallel && depth < parallel.depth_m) || (depth <= skin_m && depth < edge.depth_m) || depth < any.depth_m;
      if (!wins) continue;
      if (!((box.exposed >> face) & 1u) && !exposed(model, object, i, x + normal * depth)) {
        if (depth < covered.depth_m) covered.take(depth, normal);
        continue;
      }
      if (is_parallel && depth < parallel.depth_m) parallel.take(depth, normal);
      if (depth <= skin_m && depth < edge.depth_m) edge.take(depth, normal);
      if (depth < any.depth_m) any.take(depth, normal);
    }
  }
  if (!in_any) return false;
  const Best& chosen = edge.found() && (!parallel.found() || edge.depth_m < parallel.depth_m) ? edge
                       : parallel.found()                                                   ? parallel
                       : any.found()                                                        ? any
                                                                                            : covered;
  contact.normal = chosen.found() ? chosen.normal : entry;
  contact.depth_m = chosen.found() ? chosen.depth_m : 0.0;
  return true;
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

// separating-axis test restricted to world axes on the boxes' bounding boxes: conservative
bool boxes_may_overlap(const Box& a, const Box& b) {
  for (int axis = 0; axis < 3; ++axis) {
    double ra = 0.0, rb = 0.0;
    for (int k = 0; k < 3; ++k) {
      ra += std::abs(component(a.rotation.column(k), axis)) * component(a.half_extents_m, k);
      rb += std::abs(component(b.rotation.column(k), axis)) * component(b.half_extents_m, k);
    }
    if (std::abs(component(a.center_m, axis) - component(b.center_m, axis)) >= ra + rb - kTolerance_m) return false;
  }
  return true;
}

}  // namespace

void Model::index_boxes() {
  for (Object& o : objects) {
    if (o.type != ObjectType::boxes) continue;
    o.bounded = true;
    o.bounds_min_m = Vec3{1, 1, 1} * std::numeric_limits<double>::infinity();
    o.bounds_max_m = -o.bounds_min_m;
    for (int i = o.first_box; i < o.first_box + o.box_count; ++i) {
      Box& box = boxes[i];
      // world bounding box: centre -/+ the sum of |axis| * half extent
      Vec3 reach;
      for (int k = 0; k < 3; ++k) {
        const Vec3 a = box.rotation.column(k);
        reach += Vec3{std::abs(a.x), std::abs(a.y), std::abs(a.z)} * component(box.half_extents_m, k);
      }
      o.bounds_min_m = {std::min(o.bounds_min_m.x, box.center_m.x - reach.x), std::min(o.bounds_min_m.y, box.center_m.y - reach.y),
                        std::min(o.bounds_min_m.z, box.center_m.z - reach.z)};
      o.bounds_max_m = {std::max(o.bounds_max_m.x, box.center_m.x + reach.x), std::max(o.bounds_max_m.y, box.center_m.y + reach.y),
                        std::max(o.bounds_max_m.z, box.center_m.z + reach.z)};
      box.exposed = 0;
      for (int face = 0; face < 6; ++face) {
        // exposed when every other box lies behind the face's plane
        const Vec3 n = face_normal(box, face);
        const double plane = dot(n, box.center_m) + component(box.half_extents_m, face / 2);
        bool behind = true;
        for (int j = o.first_box; j < o.first_box + o.box_count; ++j) {
          if (j == i) continue;
          const Box& other = boxes[j];
          double extent = dot(n, other.center_m);
          for (int k = 0; k < 3; ++k) extent += std::abs(dot(n, other.rotation.column(k))) * component(other.half_extents_m, k);
          behind = behind && extent <= plane + kTolerance_m;
        }
        if (behind) box.exposed |= static_cast<std::uint8_t>(1u << face);
      }
    }
  }
}

bool objects_overlap(const Model& m, const Object& a, const Object& b) {
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

bool inside(const Model& model, const Object& object, const Vec3& x) {
  if (object.type == ObjectType::plane) return dot(object.plane_normal, x - object.plane_point_m) < 0.0;
  if (object.bounded && (x.x < object.bounds_min_m.x || x.y < object.bounds_min_m.y || x.z < object.bounds_min_m.z ||
                         x.x > object.bounds_max_m.x || x.y > object.bounds_max_m.y || x.z > object.bounds_max_m.z)) {
    return false;
  }
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    if (inside_box(model.boxes[i], x, 0.0)) return true;
  }
  return false;
}

double update_contact(const Model& model, const Object& object, const Vec3& x_prev, const Vec3& x, double skin_m,
                      ContactState& contact) {
  if (object.type == ObjectType::plane) {
    contact.normal = contact.entry_normal = object.plane_normal;
    contact.depth_m = std::max(0.0, dot(object.plane_normal, object.plane_point_m - x));
    contact.active = contact.depth_m > 0.0;
    return contact.depth_m;
  }
  if (!contact.active) {
    // a new contact remembers the face it came through (or, starting inside, the shallowest)
    if (!inside(model, object, x)) return 0.0;
    if (!crossed_face(model, object, x_prev, x, contact.entry_normal)) {
      choose_face(model, object, x, Vec3{}, std::numeric_limits<double>::infinity(), contact);
      contact.entry_normal = contact.normal;
    }
  }
  contact.active = choose_face(model, object, x, contact.entry_normal, skin_m, contact) && contact.depth_m > 0.0;
  // riding over an edge moves the contact to the new face
  if (contact.active) contact.entry_normal = contact.normal;
  else contact.depth_m = 0.0;
  return contact.depth_m;
}

}  // namespace enact::physics
