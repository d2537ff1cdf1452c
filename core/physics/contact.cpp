#include "core/physics/contact.h"

#include <array>
#include <limits>

namespace enact::physics {
namespace {

// tolerance for "on a face" and "strictly inside another box" (m)
constexpr double kTolerance_m = 1e-9;
// a face whose normal is within 120 degrees of the entry face's may push (not the opposite face)
constexpr double kOppositeCos = -0.5;
// faces considered at once: 6 for each of up to 8 boxes containing the point
constexpr int kMaxCandidates = 48;

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

struct Candidate {
  double depth_m;
  int box;
  int face;
};

// the shallowest exposed pushing face of the boxes containing x, not opposite `entry`
// (entry zero: any face); false when x is in no box
bool shallowest_face(const Model& model, const Object& object, const Vec3& x, const Vec3& entry, ContactState& contact) {
  std::array<Candidate, kMaxCandidates> c;
  int n = 0;
  bool in_any = false;
  for (int i = object.first_box; i < object.first_box + object.box_count && n + 6 <= kMaxCandidates; ++i) {
    const Box& box = model.boxes[i];
    const Vec3 local = to_local(box, x);
    if (!inside_local(box, local, 0.0)) continue;
    in_any = true;
    for (int face = 0; face < 6; ++face) {
      if (!((box.faces >> face) & 1u) || dot(face_normal(box, face), entry) < kOppositeCos) continue;
      c[n++] = {-face_distance(box, local, face), i, face};
    }
  }
  if (!in_any) return false;
  // shallowest first; a face covered by another box of the union is skipped
  for (int tried = 0; tried < n; ++tried) {
    int best = tried;
    for (int j = tried + 1; j < n; ++j) best = c[j].depth_m < c[best].depth_m ? j : best;
    std::swap(c[tried], c[best]);
    const Box& box = model.boxes[c[tried].box];
    const Vec3 normal = face_normal(box, c[tried].face);
    const bool always = (box.exposed >> c[tried].face) & 1u;
    if (!always && tried + 1 < n && !exposed(model, object, c[tried].box, x + normal * c[tried].depth_m)) continue;
    contact.normal = normal;
    contact.depth_m = c[tried].depth_m;
    return true;
  }
  // inside, but every face is opposite the entry face: keep pushing back along the entry normal
  contact.normal = entry;
  contact.depth_m = 0.0;
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
          if (j == i) continue;
          const Box& other = boxes[j];
          double reach = dot(n, other.center_m);
          for (int k = 0; k < 3; ++k) reach += std::abs(dot(n, other.rotation.column(k))) * component(other.half_extents_m, k);
          behind = behind && reach <= plane + kTolerance_m;
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
  for (int i = object.first_box; i < object.first_box + object.box_count; ++i) {
    if (inside_box(model.boxes[i], x, 0.0)) return true;
  }
  return false;
}

double update_contact(const Model& model, const Object& object, const Vec3& x_prev, const Vec3& x, ContactState& contact) {
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
      shallowest_face(model, object, x, Vec3{}, contact);
      contact.entry_normal = contact.normal;
    }
  }
  contact.active = shallowest_face(model, object, x, contact.entry_normal, contact) && contact.depth_m > 0.0;
  if (!contact.active) contact.depth_m = 0.0;
  return contact.depth_m;
}

}  // namespace enact::physics
