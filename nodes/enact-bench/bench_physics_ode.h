#pragma once
// The Open Dynamics Engine (ODE) beside ours in `enact bench physics`: the same body on the same
// boxes and planes, stepped by ODE. Built only when pkg-config finds ODE (ENACT_BENCH_ODE);
// how the scene is expressed and how it differs from ours: docs/physics.md, "A peer engine: ODE".
#include <cstddef>
#include <memory>
#include <vector>

#include "core/haptics/computer_model.h"
#include "core/math/vec3.h"
#include "core/physics/model.h"
#include "nodes/enact/json.h"
#include "core/physics/reference.h"

namespace enact::cli::ode_peer {

namespace reference = physics::reference;

// the ODE twin of a model at its rate: each point of its first body that feeds the device a
// small sphere on one position-driven ODE body, each plane and box a static geom, each contact
// a soft constraint with the ERP and CFM that give its pair's stiffness and damping at the step
class Scene {
 public:
  // throws std::runtime_error on an object the twin cannot hold (a mesh, a capsule)
  explicit Scene(const physics::Model& m);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  // the body at rest, its centre at `hand_m`
  void reset(const math::Vec3& hand_m);
  // one step with the body's centre at `hand_m`, its velocity the backward difference from the
  // last position: the force on the device, the sum of the contact joints' forces on the body
  math::Vec3 step(const math::Vec3& hand_m);
  // contact joints in the last step
  int contacts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// a median over rounds and its range
struct Spread {
  double median = 0.0;
  double min = 0.0;
  double max = 0.0;
};

// both engines along one path at one rate: ns per step, timed in alternating rounds, and the
// device force against the reference's at the same instants
struct Comparison {
  double rate_hz = 0.0;
  int rounds = 0;
  std::size_t steps = 0;
  Spread ours_ns;
  Spread ode_ns;
  Spread step_ratio;  // ODE's ns per step over ours, per round
  double ours_force_rms_error_n = 0.0;
  double ours_force_max_error_n = 0.0;
  double ode_force_rms_error_n = 0.0;
  double ode_force_max_error_n = 0.0;
  double reference_force_rms_n = 0.0;  // the scale of the forces compared
  double force_error_ratio() const { return ode_force_rms_error_n / ours_force_rms_error_n; }
};

// the scene under computer model cm along `hand` for duration_s at rate_hz in both engines
// (ours: cordis), `rounds` rounds, against cordis at reference_hz
Comparison compare(const physics::Model& scene, const haptics::ComputerModel& cm, const reference::HandPath& hand, double duration_s,
                   double rate_hz, double reference_hz, int rounds);
void print(const Comparison& c);
// the fields ode_step_ratio, ode_force_error_ratio and the object ode_peer
void json(Json& j, const Comparison& c);

}  // namespace enact::cli::ode_peer
