#pragma once
// Re-synchronising the model with the device after an interruption of the force path (a
// watchdog episode, a simulator (re)start, a long overrun): while the force was cut, the hand
// may have pushed the device deep into an object, and stepping there at once would answer
// with a jolt (hundreds of N). Instead, the first step after the interruption places the
// body just out of every object along the contact normals (the contacts' memory of the
// faces they entered through is kept), and that offset shrinks smoothly (zero speed at both
// ends) to zero over duration_s: the force grows from zero back to the model's. Allocates nothing after
// construction; never throws.
#include <cstdint>

#include "core/math/vec3.h"
#include "core/physics/model.h"
#include "core/physics/state.h"

namespace enact::sim {

class Simulator;

// the simulator node's default duration (parameter reengage_s)
constexpr double kReengageDefault_s = 0.100;

class Reengagement {
 public:
  // duration_s >= 0: how long the body takes to return from out of the objects to the device
  explicit Reengagement(double duration_s = kReengageDefault_s);

  // the force path was interrupted: the next position() re-synchronises
  void interrupt() { pending_ = true; }

  // the position to give Simulator::step for the device at device_m at time_ns: the
  // device's own, plus an offset that keeps the body's points out of the objects at the
  // first step after interrupt() and shrinks smoothly to zero over duration_s
  math::Vec3 position(const Simulator& sim, std::int64_t time_ns, const math::Vec3& device_m);

  // re-synchronisations so far, and the largest offset they needed (m)
  std::uint64_t count() const { return count_; }
  double largest_offset_m() const { return largest_m_; }

 private:
  std::int64_t duration_ns_;
  bool pending_ = false;
  math::Vec3 offset_m_;
  std::int64_t from_ns_ = 0;
  std::uint64_t count_ = 0;
  double largest_m_ = 0.0;
};

// the smallest offset (found by a few projections along the contact normals) that brings
// every point of proxy 0's body at device_m out of the objects it would penetrate, given the
// state's contact memory; zero when nothing penetrates
math::Vec3 resync_offset(const physics::Model& model, const physics::State& state, const math::Vec3& device_m);

}  // namespace enact::sim
