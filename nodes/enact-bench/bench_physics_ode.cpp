// enact bench physics's peer arm: the bridge scene in the Open Dynamics Engine, stepped along
// the same hand path as ours, timed in alternating rounds and compared with the same reference.
#include "nodes/enact-bench/bench_physics_ode.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "core/physics/state.h"
#include "core/rt/clock.h"

namespace enact::cli::ode_peer {

namespace {

using math::Vec3;
using physics::Model;

// a body point as a sphere this small, its centre the point: the contact depth is ODE's less
// the radius (a point 0.1 mm deep in a box is a sphere 0.1 mm + radius deep)
constexpr double kSphereRadius_m = 1e-5;
// the body's mass and the radius of its inertia sphere: large enough that the contacts do not
// move it within a step (16 contacts change it by about h 16 (h k + c) / M: 4e-9 of the force)
constexpr double kBodyMass_kg = 1e6;
constexpr double kBodyInertiaRadius_m = 1.0;
// a contact's way out that ends deeper than this inside another box of the same object goes
// through a covered face (coplanar faces meet within rounding)
constexpr double kCoveredDepth_m = 1e-9;

// ODE's library state: initialised once, closed at exit
void init_library() {
  struct Library {
    Library() { dInitODE2(0); }
    ~Library() { dCloseODE(); }
  };
  static const Library library;
}

Vec3 to_vec3(const dReal* v) { return {v[0], v[1], v[2]}; }

// ODE's rotation (row-major 3 x 4) of a box whose axes are the columns of r
void set_rotation(dGeomID g, const math::Mat3& r) {
  dMatrix3 m{};
  for (int i = 0; i < 3; ++i) {
    const Vec3& axis = r.column(i);
    m[0 * 4 + i] = axis.x;
    m[1 * 4 + i] = axis.y;
    m[2 * 4 + i] = axis.z;
  }
  dGeomSetRotation(g, m);
}

void* tag(std::size_t index) { return reinterpret_cast<void*>(static_cast<std::uintptr_t>(index)); }
std::size_t untag(dGeomID g) { return static_cast<std::size_t>(reinterpret_cast<std::uintptr_t>(dGeomGetData(g))); }

}  // namespace

struct Scene::Impl {
  // a sphere against one object: the pair's soft constraint and the shallowest contact found this step
  struct Pair {
    bool paired = false;  // the model has a contact pair of the point and the object
    double erp = 0.0;
    double cfm = 0.0;
    double threshold_m = 0.0;
    bool found = false;
    dContactGeom contact{};
  };

  double dt_s = 0.0;
  int objects = 0;
  dWorldID world = nullptr;
  dSpaceID body_space = nullptr;
  dSpaceID static_space = nullptr;
  dBodyID body = nullptr;
  dJointGroupID joints = nullptr;
  std::vector<Pair> pairs;  // sphere s against object o: pairs[s * objects + o]
  std::vector<std::vector<dGeomID>> boxes;  // each object's box geoms
  std::vector<dJointFeedback> feedback;
  int contacts = 0;
  Vec3 last_hand_m;

  ~Impl() {
    if (joints) dJointGroupDestroy(joints);
    if (body_space) dSpaceDestroy(body_space);
    if (static_space) dSpaceDestroy(static_space);
    if (world) dWorldDestroy(world);
  }

  // whether the point pushed out of `from` along a contact ends inside another box of its object
  bool covered(std::size_t object, dGeomID from, const Vec3& out_m) const {
    for (dGeomID g : boxes[object]) {
      if (g != from && dGeomBoxPointDepth(g, out_m.x, out_m.y, out_m.z) > kCoveredDepth_m) return true;
    }
    return false;
  }

  // dSpaceCollide2's callback: one sphere and one static geom whose bounding boxes overlap. The
  // bridge's boxes overlap at its turns: a contact whose way out goes into another box of the
  // union (through a covered face) is dropped, and of the rest only the shallowest is kept, so
  // a point inside a union is pushed once, out of the union (as in ours)
  static void near(void* data, dGeomID a, dGeomID b) {
    Impl& self = *static_cast<Impl*>(data);
    const bool a_sphere = dGeomGetSpace(a) == self.body_space;
    dGeomID sphere = a_sphere ? a : b;
    dGeomID other = a_sphere ? b : a;
    const std::size_t object = untag(other);
    Pair& p = self.pairs[untag(sphere) * self.objects + object];
    if (!p.paired) return;
    dContactGeom c;
    if (dCollide(sphere, other, 1, &c, sizeof c) == 0) return;
    c.depth -= kSphereRadius_m + p.threshold_m;
    if (c.depth <= 0.0 || (p.found && c.depth >= p.contact.depth)) return;
    // the normal points into the sphere: moved along it by the depth, the point is out
    if (self.covered(object, other, to_vec3(dGeomGetPosition(sphere)) + to_vec3(c.normal) * c.depth)) return;
    p.contact = c;
    p.found = true;
  }
};

Scene::Scene(const Model& m) : impl_(std::make_unique<Impl>()) {
  init_library();
  Impl& s = *impl_;
  if (m.proxies.empty()) throw std::runtime_error(m.source + ": the ODE peer needs a body");
  s.dt_s = m.dt_s;
  s.objects = static_cast<int>(m.objects.size());
  s.world = dWorldCreate();
  dWorldSetGravity(s.world, 0.0, 0.0, 0.0);
  dWorldSetContactSurfaceLayer(s.world, 0.0);
  dWorldSetContactMaxCorrectingVel(s.world, dInfinity);
  s.body_space = dSimpleSpaceCreate(nullptr);
  s.static_space = dSimpleSpaceCreate(nullptr);
  s.joints = dJointGroupCreate(0);
  s.body = dBodyCreate(s.world);
  dMass mass;
  dMassSetSphereTotal(&mass, kBodyMass_kg, kBodyInertiaRadius_m);
  dBodySetMass(s.body, &mass);
  dBodySetGravityMode(s.body, 0);

  // the static objects: planes and the boxes of unions
  s.boxes.resize(m.objects.size());
  for (std::size_t o = 0; o < m.objects.size(); ++o) {
    const physics::Object& object = m.objects[o];
    if (object.type == physics::ObjectType::plane) {
      const Vec3& n = object.plane_normal;
      dGeomSetData(dCreatePlane(s.static_space, n.x, n.y, n.z, math::dot(n, object.plane_point_m)), tag(o));
      continue;
    }
    if (object.type != physics::ObjectType::boxes) {
      throw std::runtime_error(m.source + ": object '" + object.name + "' is a " + object.shape + ": the ODE peer holds planes and boxes only");
    }
    for (int b = object.first_box; b < object.first_box + object.box_count; ++b) {
      const physics::Box& box = m.boxes[b];
      const Vec3 size = box.half_extents_m * 2.0;
      dGeomID g = dCreateBox(s.static_space, size.x, size.y, size.z);
      dGeomSetPosition(g, box.center_m.x, box.center_m.y, box.center_m.z);
      set_rotation(g, box.rotation);
      dGeomSetData(g, tag(o));
      s.boxes[o].push_back(g);
    }
  }

  // the body: a sphere for each point of the first body that feeds the device
  std::vector<int> spheres;
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const physics::Point& p = m.points[i];
    if (p.proxy != 0 || !p.feeds_device || p.kind != physics::PointKind::kinematic) continue;
    dGeomID g = dCreateSphere(s.body_space, kSphereRadius_m);
    dGeomSetBody(g, s.body);
    dGeomSetOffsetPosition(g, p.offset_m.x, p.offset_m.y, p.offset_m.z);
    dGeomSetData(g, tag(spheres.size()));
    spheres.push_back(static_cast<int>(i));
  }
  // each pair's soft constraint (ODE's manual: ERP = h k / (h k + c), CFM = 1 / (h k + c))
  s.pairs.resize(spheres.size() * m.objects.size());
  for (const physics::ContactPair& c : m.contacts) {
    const auto it = std::find(spheres.begin(), spheres.end(), c.point);
    if (it == spheres.end()) continue;
    Impl::Pair& p = s.pairs[static_cast<std::size_t>(it - spheres.begin()) * m.objects.size() + c.object];
    const double hk_c = m.dt_s * c.stiffness_n_per_m + c.damping_n_s_per_m;
    p = {.paired = true, .erp = m.dt_s * c.stiffness_n_per_m / hk_c, .cfm = 1.0 / hk_c, .threshold_m = m.points[c.point].contact_threshold_m};
  }
  s.feedback.resize(s.pairs.size());
  reset(m.points[m.proxies[0].point].position_m);
}

Scene::~Scene() = default;

void Scene::reset(const Vec3& hand_m) {
  Impl& s = *impl_;
  s.last_hand_m = hand_m;
  dBodySetPosition(s.body, hand_m.x, hand_m.y, hand_m.z);
  dBodySetLinearVel(s.body, 0.0, 0.0, 0.0);
}

Vec3 Scene::step(const Vec3& hand_m) {
  Impl& s = *impl_;
  // the body where the hand is, moving as it moved over the last step, never turning
  const Vec3 v = (hand_m - s.last_hand_m) * (1.0 / s.dt_s);
  s.last_hand_m = hand_m;
  static const dQuaternion upright{1.0, 0.0, 0.0, 0.0};
  dBodySetPosition(s.body, hand_m.x, hand_m.y, hand_m.z);
  dBodySetQuaternion(s.body, upright);
  dBodySetLinearVel(s.body, v.x, v.y, v.z);
  dBodySetAngularVel(s.body, 0.0, 0.0, 0.0);
  // contacts: ODE's broad phase and narrow phase, one joint per sphere and object
  for (Impl::Pair& p : s.pairs) p.found = false;
  dSpaceCollide2(reinterpret_cast<dGeomID>(s.body_space), reinterpret_cast<dGeomID>(s.static_space), &s, &Impl::near);
  s.contacts = 0;
  for (std::size_t k = 0; k < s.pairs.size(); ++k) {
    const Impl::Pair& p = s.pairs[k];
    if (!p.found) continue;
    dContact contact{};
    contact.surface.mode = dContactSoftERP | dContactSoftCFM;
    contact.surface.mu = 0.0;
    contact.surface.soft_erp = p.erp;
    contact.surface.soft_cfm = p.cfm;
    contact.geom = p.contact;
    dJointID j = dJointCreateContact(s.world, s.joints, &contact);
    dJointAttach(j, s.body, nullptr);
    dJointSetFeedback(j, &s.feedback[k]);
    ++s.contacts;
  }
  dWorldStep(s.world, s.dt_s);
  Vec3 force;
  for (std::size_t k = 0; k < s.pairs.size(); ++k) {
    if (s.pairs[k].found) force += to_vec3(s.feedback[k].f1);
  }
  dJointGroupEmpty(s.joints);
  return force;
}

int Scene::contacts() const { return impl_->contacts; }

namespace {

Spread spread(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return {v[v.size() / 2], v.front(), v.back()};
}

// wall-clock ns per step of one pass along the motion
template <class Step>
double ns_per_step(const std::vector<Vec3>& motion, Step&& step) {
  const std::int64_t start_ns = rt::now_ns();
  for (const Vec3& p : motion) step(p);
  return static_cast<double>(rt::now_ns() - start_ns) / static_cast<double>(motion.size());
}

// |F - F_ref| over a pass: root mean square and largest
template <class Step>
void force_errors(const std::vector<Vec3>& motion, const std::vector<Vec3>& reference, Step&& step, double& rms_n, double& max_n) {
  double sum_squares = 0.0;
  max_n = 0.0;
  for (std::size_t n = 0; n < motion.size(); ++n) {
    const double e = math::norm(step(motion[n]) - reference[n]);
    sum_squares += e * e;
    max_n = std::max(max_n, e);
  }
  rms_n = std::sqrt(sum_squares / static_cast<double>(motion.size()));
}

}  // namespace

Comparison compare(const Model& scene, const haptics::ComputerModel& cm, const reference::HandPath& hand, double duration_s,
                   double rate_hz, double reference_hz, int rounds) {
  Model with_cm = scene;
  haptics::apply(cm, with_cm);
  const Model m = reference::sweep_model(with_cm, hand(0.0), physics::Integrator::cordis, rate_hz);
  const std::vector<Vec3> motion = reference::sample(hand, duration_s, rate_hz);
  const std::vector<Vec3> ref = reference::reference_forces(with_cm, hand, duration_s, rate_hz, reference_hz);
  const physics::State initial = physics::make_state(m);
  physics::State ours = initial;
  Scene ode(m);
  auto ours_step = [&m, &ours](const Vec3& p) {
    ours.proxy_position_m[0] = p;
    physics::step(m, ours);
    return ours.proxy_force_n[0];
  };
  auto ode_step = [&ode](const Vec3& p) { return ode.step(p); };

  Comparison c;
  c.rate_hz = rate_hz;
  c.rounds = rounds;
  c.steps = motion.size();
  force_errors(motion, ref, ours_step, c.ours_force_rms_error_n, c.ours_force_max_error_n);
  force_errors(motion, ref, ode_step, c.ode_force_rms_error_n, c.ode_force_max_error_n);
  double sum_squares = 0.0;
  for (const Vec3& f : ref) sum_squares += math::dot(f, f);
  c.reference_force_rms_n = std::sqrt(sum_squares / static_cast<double>(ref.size()));

  // the arms alternate, each round starting with the other, so both share the machine's drifts
  std::vector<double> ours_ns, ode_ns, ratio;
  for (int r = 0; r < rounds; ++r) {
    std::fprintf(stderr, "enact bench: the ODE peer, round %d of %d\n", r + 1, rounds);
    double t_ours = 0.0, t_ode = 0.0;
    for (int arm = 0; arm < 2; ++arm) {
      if ((arm + r) % 2 == 0) {
        ours = initial;
        t_ours = ns_per_step(motion, ours_step);
      } else {
        ode.reset(hand(0.0));
        t_ode = ns_per_step(motion, ode_step);
      }
    }
    ours_ns.push_back(t_ours);
    ode_ns.push_back(t_ode);
    ratio.push_back(t_ode / t_ours);
  }
  c.ours_ns = spread(ours_ns);
  c.ode_ns = spread(ode_ns);
  c.step_ratio = spread(ratio);
  return c;
}

void print(const Comparison& c) {
  std::printf("\nODE peer     the bridge along its scripted path at %.0f kHz (CM1), %zu steps, %d alternating rounds (median, min-max)\n",
              c.rate_hz / 1e3, c.steps, c.rounds);
  std::printf("  ours (cordis)  %9.1f ns/step (%.1f-%.1f)  F rms err %.3e N, max %.3e N\n", c.ours_ns.median, c.ours_ns.min, c.ours_ns.max,
              c.ours_force_rms_error_n, c.ours_force_max_error_n);
  std::printf("  ODE dWorldStep %9.1f ns/step (%.1f-%.1f)  F rms err %.3e N, max %.3e N\n", c.ode_ns.median, c.ode_ns.min, c.ode_ns.max,
              c.ode_force_rms_error_n, c.ode_force_max_error_n);
  std::printf("  ODE / ours: step x%.2f (x%.2f-x%.2f), force rms error x%.3g (reference force rms %.3f N)\n", c.step_ratio.median,
              c.step_ratio.min, c.step_ratio.max, c.force_error_ratio(), c.reference_force_rms_n);
}

void json(Json& j, const Comparison& c) {
  j.field("ode_step_ratio", c.step_ratio.median).field("ode_force_error_ratio", c.force_error_ratio());
  j.key("ode_peer").begin_object().field("rate_hz", c.rate_hz).field("rounds", c.rounds).field("steps", static_cast<long long>(c.steps));
  const auto spread_json = [&j](const char* name, const Spread& s) {
    j.key(name).begin_object().field("median", s.median).field("min", s.min).field("max", s.max).end_object();
  };
  spread_json("ours_ns_per_step", c.ours_ns);
  spread_json("ode_ns_per_step", c.ode_ns);
  spread_json("step_ratio", c.step_ratio);
  j.field("ours_force_rms_error_n", c.ours_force_rms_error_n).field("ours_force_max_error_n", c.ours_force_max_error_n);
  j.field("ode_force_rms_error_n", c.ode_force_rms_error_n).field("ode_force_max_error_n", c.ode_force_max_error_n);
  j.field("reference_force_rms_n", c.reference_force_rms_n).end_object();
}

}  // namespace enact::cli::ode_peer
