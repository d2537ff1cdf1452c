#pragma once
// The per-step state of a scene: everything that changes while it runs. Sized once from
// the Model (make_state); trivial to reset, copy and log.
#include <cstdint>
#include <vector>

#include "core/physics/model.h"

namespace enact::physics {

// one contact pair. A point inside an object is pushed out through the shallowest face
// of the object's surface, except the face opposite the one it entered through: it is
// never pushed on towards the far side, however fast it came in (docs/physics.md, "Contact guarantees").
struct ContactState {
  bool active = false;
  Vec3 entry_normal;      // outward normal of the face the point entered through
  Vec3 normal;            // outward normal of the face pushing now (unit)
  double depth_m = 0.0;   // penetration below that face (> 0 while active)
  int box = -1;           // the box and face pushing now (boxes only; -1 for planes)
  int face = -1;
  // meshes: the triangle nearest last step. Its hold (hold_at_m, hold_r2): outside, the point
  // cannot reach the surface; inside, no other triangle can become nearer
  int triangle = -1;
  // and the ring of the triangle the last search (at ring_at_m) found (Mesh::ring; -1: none):
  // every triangle outside it was ring_bound_m or farther from ring_at_m, so one of the ring's
  // is nearest while it is nearer than that less the point's travel
  int ring_of = -1;
  Vec3 ring_at_m;
  double ring_bound_m = 0.0;
  // the boxes of the object within a margin of `near_at_m` (bit i: box first_box + i): while
  // the point stays within that margin of near_at_m it can only be inside these
  std::uint64_t near_boxes = 0;
  Vec3 near_at_m;
  bool near_valid = false;
  // the held face: while the point stays closer than sqrt(hold_r2) to hold_at_m, the face that
  // pushes keeps pushing (no other face of the object can take over, the point stays in its
  // box) unless one of the coplanar faces in `ties` becomes shallower, checked each step
  // (contact.cpp, plan_hold). hold_r2 0: none
  struct Tie {
    int box = -1;
    int face = -1;
  };
  Vec3 hold_at_m;
  double hold_r2 = 0.0;
  Tie ties[2];
  // passive pairs (ContactPair::passive), a passivity observer after Hannaford & Ryu (2002):
  // the energy the contact's spring absorbed and has not returned (J), from the discrete work
  // the three integrators give, F(n) . (x(n+1) - x(n-1)) / 2; and this step's spring and
  // damper terms along `normal` (N) and x(n-1), for that work once x(n+1) is known
  double ledger_j = 0.0;
  double spring_n = 0.0;
  double damper_n = 0.0;
  Vec3 work_from_m;
  // friction (ContactPair::friction): the anchor the point is tied to by the tangential spring,
  // on the tangent plane through the point; set on the first step the contact pushes, released
  // on the first it does not. sliding: it slipped last step (the dynamic limit holds until it sticks)
  Vec3 anchor_m;
  bool anchored = false;
  bool sliding = false;
};

// the contact pairs of one device body against one object: each step, when a sphere around
// the body is apart from the object, none of them can touch and all are skipped
struct PairGroup {
  int proxy = -1;
  int object = -1;
  Vec3 centre_offset_m;  // the sphere's centre relative to the proxy
  double radius_m = 0.0; // it holds every body point of the group
};

// consecutive contact pairs of one group (-1: none), in the order of Model::contacts
struct PairRun {
  int first = 0;
  int count = 0;
  int group = -1;
};

enum class Fault : std::uint8_t { none, nonfinite_input, nonfinite_state, runaway_position, runaway_speed };

struct State {
  // per point
  std::vector<Vec3> x;       // position (m)
  std::vector<Vec3> x_prev;  // position one step earlier (m)
  std::vector<Vec3> v;       // velocity (m/s)
  std::vector<Vec3> f;       // force accumulated this step (N)
  std::vector<std::uint8_t> in_contact;  // penetrating an object or a contact link (threshold ignored)
  std::vector<double> k_diag;  // implicit_euler: stiffness acting on the point this step (N/m)
  std::vector<double> z_diag;  // implicit_euler: damping acting on the point this step (N s/m)
  // per contact pair
  std::vector<ContactState> contacts;
  // per proxy: input (device position) and output (force to send to the device)
  std::vector<Vec3> proxy_position_m;
  std::vector<Vec3> proxy_force_n;
  // deformable bodies (Proxy::deformable): per point, the contact force on a body mass this
  // step apart from its links and gravity (empty without a deformable body); per proxy, the
  // proxy links' reactions the device feels (zero for a rigid body)
  std::vector<Vec3> body_contact_n;
  std::vector<Vec3> coupling_n;

  // which points the step integrates and which follow a proxy (from make_state)
  std::vector<int> dynamic;
  std::vector<int> kinematic;
  // the passive contact pairs (indices into Model::contacts)
  std::vector<int> passive;
  // pair culling: the groups, the pairs as runs of one group (group -1: the pairs of dynamic
  // points and passive pairs, evaluated every step), and which groups are apart this step.
  // With cull false every pair is evaluated every step (the reference: the same forces bit
  // for bit, in the same order)
  std::vector<PairGroup> groups;
  std::vector<PairRun> runs;
  std::vector<std::uint8_t> group_apart;
  bool cull = true;
  // with hold false every contact takes the full face test every step (the reference for
  // ContactState's held face)
  bool hold = true;

  std::int64_t steps = 0;
  double time_s = 0.0;
  std::uint64_t faults = 0;  // divergence guard trips since make_state
  Fault last_fault = Fault::none;
  int last_fault_point = -1;
};

// the contact force on body point i this step: a rigid body's point has no other force, a
// deformable body's mass its contact force apart from its links
inline Vec3 body_contact_force(const Model& model, const State& state, int i) {
  return model.points[i].kind == PointKind::dynamic ? state.body_contact_n[i] : state.f[i];
}

// a state sized for the model, at its initial conditions
State make_state(const Model& model);
// back to initial conditions (fault counters are kept)
void reset(const Model& model, State& state);
// one step of dt: kinematic points follow state.proxy_position_m, forces, integration,
// divergence guard, proxy forces. Allocates nothing, never throws; a fault zeroes the
// proxy forces, resets the dynamic points and is counted.
void step(const Model& model, State& state);

const char* to_string(Fault fault);
const char* to_string(Integrator integrator);

}  // namespace enact::physics
