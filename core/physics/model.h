#pragma once
// The static description of a mass-interaction scene (CORDIS-ANIMA tradition): points,
// links, rigid objects, the contact pairs between them, and the device proxies.
// Built once at load time (see scene.h); the step reads it and never resizes it.
// Parameters are physical (kg, N/m, N s/m, m), so one scene runs at any rate.
#include <cstdint>
#include <string>
#include <vector>

#include "core/math/vec3.h"
#include "core/physics/mesh.h"

namespace enact::physics {

// the engine's vector and rotation types (core/math)
using math::Mat3;
using math::rotation_rpy;
using math::Vec3;

enum class Integrator : std::uint8_t {
  cordis,            // x(n+1) = 2x(n) - x(n-1) + F(n) dt^2 / m, velocities as backward differences
  symplectic_euler,  // v(n+1) = v(n) + F(n) dt / m, x(n+1) = x(n) + v(n+1) dt
  implicit_euler,    // linearly implicit in velocity with each mass's own stiffness and damping
};

enum class PointKind : std::uint8_t {
  dynamic,    // a mass, integrated
  fixed,      // a fixed point (CORDIS-ANIMA "SOL")
  kinematic,  // positioned by a device proxy: the proxy itself, or a mass of its rigid exploratory body
};

struct Point {
  std::string name;
  PointKind kind = PointKind::dynamic;
  double mass_kg = 0.0;                 // dynamic points only
  Vec3 position_m;                      // initial position (fixed: the position)
  Vec3 velocity_m_per_s;                // initial velocity (dynamic points)
  int proxy = -1;                       // body points (kinematic, or a deformable body's mass): index into Model::proxies
  Vec3 offset_m;                        // body points: (rest) position relative to the proxy
  // haptic rendering of this point's contacts, set by a computer model (core/haptics)
  bool feeds_device = true;             // its force is part of what the proxy's device feels
  double contact_threshold_m = 0.0;     // penetration before any contact force acts
  int line = 0;                         // line in the scene file, for messages
};

enum class LinkType : std::uint8_t {
  spring,            // f = k (d - l0)
  damper,            // f = z d'
  spring_damper,     // both
  contact,           // "buttee": k (d - threshold) + z d', only while d < threshold, push only
  nonlinear_spring,  // f = k e + c e^3, incremental stiffness clipped to max_stiffness
};

struct Link {
  std::string name;
  LinkType type = LinkType::spring;
  int a = -1;  // point indices
  int b = -1;
  double stiffness_n_per_m = 0.0;
  double damping_n_s_per_m = 0.0;
  double rest_length_m = 0.0;        // 0: isotropic (f along b - a, no direction singularity)
  double threshold_m = 0.0;          // contact: acts while the distance is below this
  double cubic_n_per_m3 = 0.0;       // nonlinear_spring: c
  double max_stiffness_n_per_m = 0.0;  // nonlinear_spring: clip of k + 3 c e^2
  double clip_elongation_m = 0.0;    // nonlinear_spring: |e| past which the stiffness is max (derived)
  int line = 0;

  // the largest stiffness this link can present (for stability analysis)
  double peak_stiffness_n_per_m() const {
    return type == LinkType::nonlinear_spring ? max_stiffness_n_per_m : stiffness_n_per_m;
  }
};

// an oriented box; a rigid object is a plane or a union of boxes (a single box is a union of one)
struct Box {
  Vec3 center_m;
  Vec3 half_extents_m;
  Mat3 rotation;  // columns: the box axes in world coordinates
  std::uint8_t faces = 0x3f;  // bit f: face f (+x, -x, +y, -y, +z, -z) can push (a path's base cannot)
  std::uint8_t exposed = 0;   // bit f: no other box of the union can cover face f (set by index_boxes)
};

// a rigid object is a plane, a union of boxes (a box, a path), a closed triangle mesh (a mesh
// file, a height map) or a capsule (a sphere: a capsule of zero length)
enum class ObjectType : std::uint8_t { plane, boxes, mesh, capsule };

// a polyline centerline, kept for objects built as a path (the bridge) and for the task: tools
// place paths on it
struct PathGeometry {
  std::vector<Vec3> centerline_m;  // z = top surface
  double width_m = 0.0;
  double bottom_z_m = 0.0;
  double top_z_m = 0.0;
};

struct Object {
  std::string name;
  ObjectType type = ObjectType::plane;
  Vec3 plane_point_m;        // plane: a point on the surface
  Vec3 plane_normal;         // plane: unit outward normal (solid on the other side)
  int first_box = 0;         // boxes: index into Model::boxes
  int box_count = 0;
  bool is_path = false;      // boxes built from a path: `path` holds its centerline
  PathGeometry path;
  int mesh = -1;             // mesh: index into Model::meshes
  Vec3 axis_from_m;          // capsule: its axis, from one end to the other (equal: a sphere)
  Vec3 axis_to_m;
  double radius_m = 0.0;     // capsule: the distance of its surface from the axis
  Vec3 axis_normal;          // capsule: the push on a point exactly on the axis (unit)
  std::string shape;         // the scene's type: (plane, box, union, path, mesh, heightmap, sphere, capsule)
  int line = 0;
};

// Coulomb friction with stiction on a contact pair (scene key friction:): a tangential spring
// ties the point to an anchor that slides once the spring pulls harder than the limit
// (step.cpp, friction_force; ContactState::anchor_m)
struct Friction {
  double static_coeff = 0.0;       // the most the spring holds while stuck, per newton of normal force
  double dynamic_coeff = 0.0;      // what it pulls with while sliding, per newton of normal force (<= static)
  double stiffness_n_per_m = 0.0;  // the anchor spring's; 0: no friction (the default)
  bool enabled() const { return stiffness_n_per_m > 0.0; }
};

// a point against a rigid object: unilateral visco-elastic contact
struct ContactPair {
  int point = -1;
  int object = -1;
  double stiffness_n_per_m = 0.0;
  double damping_n_s_per_m = 0.0;
  double edge_skin_m = 0.001;  // a point this close below another face rides over the edge onto it
  int line = 0;
  // energy-consistent (scene key passive: true): the spring never returns more energy than it
  // absorbed, and returns what it holds on the step the point leaves (ContactState::ledger_j)
  bool passive = false;
  Friction friction;  // none by default: the normal force alone, as without the key
};

// a deformable exploratory body (scene key body.deformable): each grid mass is a dynamic mass
// of its own, tied to its rest place on the proxy (proxy offset + grid offset) by a proxy link
// and to its row and column neighbours by grid links, all linear visco-elastic (no rest
// length: f = k (d - d_rest) + z d', d the vector between the two ends). The device feels the
// proxy links' reactions of the masses that feed it (step.cpp, body_links)
struct DeformableBody {
  double mass_kg = 0.0;                    // each grid mass; 0: the rigid body
  double proxy_stiffness_n_per_m = 0.0;    // each proxy link
  double proxy_damping_n_s_per_m = 0.0;
  double grid_stiffness_n_per_m = 0.0;     // each grid link (0: masses tied to the proxy only)
  double grid_damping_n_s_per_m = 0.0;
  int line = 0;
  bool enabled() const { return mass_kg > 0.0; }
};

// a device proxy: a point whose position the device imposes, with an exploratory body of
// rows x cols masses attached to it (never rotating): rigidly (kinematic points; forces on all
// of them are summed and sent back to the device) or through links (`deformable`)
struct Proxy {
  std::string name;
  int point = -1;        // the proxy point itself (the body's centre)
  int first_body = -1;   // first grid point; grid point (r, c) is first_body + r * cols + c
  int rows = 0;
  int cols = 0;
  double pitch_m = 0.0;
  DeformableBody deformable;  // disabled: the rigid grid
  int line = 0;
};

struct DivergenceLimits {
  double max_position_m = 10.0;     // any dynamic point farther from the origin is a runaway
  double max_speed_m_per_s = 1.0e3; // any dynamic point faster is a runaway
};

struct Model {
  std::string name;
  std::string source;  // file the scene was loaded from
  Integrator integrator = Integrator::cordis;
  double rate_hz = 5000.0;
  double dt_s = 1.0 / 5000.0;
  Vec3 gravity_m_per_s2;
  DivergenceLimits limits;
  std::string device_profile;  // optional: device whose passivity bound is checked
  std::string task_surface;    // optional: object whose top surface the task is about
  PathGeometry task_path;      // with a task: the line along its top (a path object's own centreline), the top's height and width

  std::vector<Point> points;
  std::vector<Link> links;
  std::vector<Box> boxes;
  std::vector<Object> objects;
  std::vector<Mesh> meshes;
  std::vector<ContactPair> contacts;
  std::vector<Proxy> proxies;

  // change the rate (1 Hz .. 1 MHz); parameters are physical so nothing else changes
  void set_rate(double hz);
  int find_point(const std::string& name) const;   // -1 when absent
  int find_object(const std::string& name) const;  // -1 when absent
  // make proxy `proxy`'s grid deformable: each grid mass dynamic, of body.mass_kg, at rest at
  // its grid offset (the scene key body.deformable)
  void make_deformable(int proxy, const DeformableBody& body);
  // precompute which box faces no other box of their union can cover (a speed-up only:
  // without it such faces are checked when they matter)
  void index_boxes();
};

}  // namespace enact::physics
