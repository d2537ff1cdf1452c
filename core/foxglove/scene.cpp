#include "core/foxglove/scene.h"

#include <algorithm>
#include <cmath>

#include "core/graph/temp_folder.h"
#include "core/physics/scene.h"

namespace enact::foxglove {
namespace {

using ::foxglove::Color;
using ::foxglove::Pose;

constexpr double kFloorThickness_m = 0.001;
constexpr double kFloorMargin_m = 0.02;

void set(::foxglove::Vector3& v, const math::Vec3& p) {
  v.set_x(p.x);
  v.set_y(p.y);
  v.set_z(p.z);
}

void set(Color& c, double r, double g, double b, double a) {
  c.set_r(r);
  c.set_g(g);
  c.set_b(b);
  c.set_a(a);
}

// the quaternion of a rotation matrix (Shepperd's method: the largest of w, x, y, z first)
void set(::foxglove::Quaternion& q, const math::Mat3& m) {
  const double m00 = m.c0.x, m11 = m.c1.y, m22 = m.c2.z;
  const double m01 = m.c1.x, m10 = m.c0.y, m02 = m.c2.x, m20 = m.c0.z, m12 = m.c2.y, m21 = m.c1.z;
  const double trace = m00 + m11 + m22;
  double w, x, y, z;
  if (trace > 0.0) {
    const double s = 2.0 * std::sqrt(1.0 + trace);
    w = 0.25 * s, x = (m21 - m12) / s, y = (m02 - m20) / s, z = (m10 - m01) / s;
  } else if (m00 > m11 && m00 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m00 - m11 - m22);
    w = (m21 - m12) / s, x = 0.25 * s, y = (m01 + m10) / s, z = (m02 + m20) / s;
  } else if (m11 > m22) {
    const double s = 2.0 * std::sqrt(1.0 + m11 - m00 - m22);
    w = (m02 - m20) / s, x = (m01 + m10) / s, y = 0.25 * s, z = (m12 + m21) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + m22 - m00 - m11);
    w = (m10 - m01) / s, x = (m02 + m20) / s, y = (m12 + m21) / s, z = 0.25 * s;
  }
  q.set_x(x);
  q.set_y(y);
  q.set_z(z);
  q.set_w(w);
}

void set_pose(Pose& pose, const math::Vec3& position, const math::Mat3& rotation = {}) {
  set(*pose.mutable_position(), position);
  set(*pose.mutable_orientation(), rotation);
}

math::Vec3 cross(const math::Vec3& a, const math::Vec3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

// the rotation taking +x to the unit vector d (for an arrow)
math::Mat3 rotation_to(const math::Vec3& d) {
  // a second axis not parallel to d, then a right-handed frame around d
  const math::Vec3 helper = std::abs(d.z) < 0.9 ? math::Vec3{0, 0, 1} : math::Vec3{0, 1, 0};
  math::Vec3 y = cross(helper, d);
  y = y * (1.0 / norm(y));
  return math::Mat3{d, y, cross(d, y)};
}

}  // namespace

SceneConverter::SceneConverter(const physics::Model& model) : model_(model) {
  fixed_.set_frame_id(kSceneFrame);
  fixed_.set_id("bridge");
  const int surface = model.task_surface.empty() ? -1 : model.find_object(model.task_surface);
  math::Vec3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  std::optional<double> floor_z_m;
  // every box of every object: the task's surface in sand, others in grey
  for (std::size_t o = 0; o < model.objects.size(); ++o) {
    const physics::Object& obj = model.objects[o];
    if (obj.type == physics::ObjectType::plane) {
      if (obj.plane_normal.z > 0.99) floor_z_m = std::max(floor_z_m.value_or(-1e9), obj.plane_point_m.z);
      continue;
    }
    for (int b = obj.first_box; b < obj.first_box + obj.box_count; ++b) {
      const physics::Box& box = model.boxes[b];
      auto& cube = *fixed_.add_cubes();
      set_pose(*cube.mutable_pose(), box.center_m, box.rotation);
      set(*cube.mutable_size(), box.half_extents_m * 2.0);
      if (static_cast<int>(o) == surface) set(*cube.mutable_color(), 0.85, 0.72, 0.45, 1.0);
      else set(*cube.mutable_color(), 0.6, 0.6, 0.6, 1.0);
      const double r = norm(box.half_extents_m);
      lo = {std::min(lo.x, box.center_m.x - r), std::min(lo.y, box.center_m.y - r), std::min(lo.z, box.center_m.z - r)};
      hi = {std::max(hi.x, box.center_m.x + r), std::max(hi.y, box.center_m.y + r), std::max(hi.z, box.center_m.z + r)};
    }
  }
  // the floor: a thin slab under everything, its top on the plane
  if (floor_z_m) {
    if (lo.x > hi.x) lo = hi = {0, 0, 0};
    auto& floor = *fixed_.add_cubes();
    const math::Vec3 centre{(lo.x + hi.x) / 2, (lo.y + hi.y) / 2, *floor_z_m - kFloorThickness_m / 2};
    set_pose(*floor.mutable_pose(), centre);
    set(*floor.mutable_size(), math::Vec3{hi.x - lo.x + 2 * kFloorMargin_m, hi.y - lo.y + 2 * kFloorMargin_m, kFloorThickness_m});
    set(*floor.mutable_color(), 0.3, 0.35, 0.4, 1.0);
  }
}

void SceneConverter::convert(const msgs::SceneState& state, ::foxglove::SceneUpdate& out) const {
  out.Clear();
  const std::int64_t t_ns = static_cast<std::int64_t>(state.header().stamp_ns());
  ::foxglove::SceneEntity& fixed = *out.add_entities();
  fixed = fixed_;
  ::foxglove::SceneEntity& body = *out.add_entities();
  body.set_frame_id(kSceneFrame);
  body.set_id("body");
  for (auto* e : {&fixed, &body}) {
    e->mutable_timestamp()->set_seconds(t_ns / 1'000'000'000);
    e->mutable_timestamp()->set_nanos(static_cast<std::int32_t>(t_ns % 1'000'000'000));
  }
  const math::Vec3 centre{state.body_position().x(), state.body_position().y(), state.body_position().z()};
  // the grid's masses, red while in contact
  if (!model_.proxies.empty()) {
    const physics::Proxy& proxy = model_.proxies[0];
    const double diameter_m = std::max(proxy.pitch_m, 1e-4) * 0.6;
    for (int i = 0; i < proxy.rows * proxy.cols; ++i) {
      auto& s = *body.add_spheres();
      set_pose(*s.mutable_pose(), centre + model_.points[proxy.first_body + i].offset_m);
      set(*s.mutable_size(), math::Vec3{diameter_m, diameter_m, diameter_m});
      const bool contact = i < state.in_contact_size() && state.in_contact(i);
      if (contact) set(*s.mutable_color(), 0.9, 0.15, 0.1, 1.0);
      else set(*s.mutable_color(), 0.75, 0.75, 0.8, 1.0);
    }
  }
  // the force sent to the device, from the body's centre
  const math::Vec3 f{state.resultant_force().x(), state.resultant_force().y(), state.resultant_force().z()};
  const double magnitude_n = norm(f);
  if (magnitude_n > 1e-9) {
    const double length_m = magnitude_n * kArrowLength_m_per_n;
    auto& a = *body.add_arrows();
    set_pose(*a.mutable_pose(), centre, rotation_to(f * (1.0 / magnitude_n)));
    a.set_shaft_length(length_m * 0.8);
    a.set_head_length(length_m * 0.2);
    a.set_shaft_diameter(0.0006);
    a.set_head_diameter(0.0015);
    set(*a.mutable_color(), 0.2, 0.5, 1.0, 1.0);
  }
}

SceneConverter converter_for(const graph::NamedScene& scene) {
  const graph::TempFolder folder;
  return SceneConverter(physics::load_scene(folder.put("scene", "scene.yaml", scene.data, scene.beside)));
}

}  // namespace enact::foxglove
