#pragma once
// The hand holding a simulated force-feedback device. The simulated device couples its
// end-effector to the hand through a spring-damper (the hand impedance) pulling towards
// the hand's target: where the hand means to be. A HandSource gives that target over time:
// a scripted path (ScriptedHand) or a virtual subject (VirtualSubject) that reacts to what
// it feels. One mechanism: the device asks its source for the target at every substep.
#include <cstdint>

#include "core/task/trajectory.h"
#include "core/math/vec3.h"

namespace enact::devices {

// what the hand feels at one time, as a person holding the handle would
struct HandFeel {
  math::Vec3 handle_m;          // where the handle (and the hand around it) is
  math::Vec3 handle_m_per_s;    // how fast it moves
  math::Vec3 force_on_hand_n;   // the force the handle pushes the hand with
};

// the hand impedance of the device the hand holds, and where the trial starts
struct HandStart {
  math::Vec3 start_m;                  // the handle's position at time 0, at rest
  double hand_stiffness_n_per_m = 0.0;    // the spring between the hand target and the handle
};

class HandSource {
 public:
  virtual ~HandSource();
  // a new trial at time 0, the handle at rest at start.start_m
  virtual void reset(const HandStart& start) noexcept = 0;
  // the target at time_ns (ns since the device's clock started; never decreasing), given
  // what the hand feels at that time. Allocates nothing, never throws.
  virtual math::Vec3 target(std::int64_t time_ns, const HandFeel& feel) noexcept = 0;
  // whether the hand also has a fingertip on a tactile pin array (then call feel_pins)
  virtual bool feels_pins() const { return false; }
  // the pins under the fingertip as the tactile device physically shows them now: levels
  // 0 (down) .. 1 (up), rows * cols of them, pin i = row * cols + col, row 0 the far row
  // (+y), col 0 the left column (-x). Allocates nothing.
  virtual void feel_pins(const float* levels, int rows, int cols) noexcept;
};

// a hand that follows a path (t_s from the clock start), or holds the start when the path
// is empty; it feels nothing
class ScriptedHand final : public HandSource {
 public:
  explicit ScriptedHand(task::Trajectory path = {});
  void reset(const HandStart& start) noexcept override;
  math::Vec3 target(std::int64_t time_ns, const HandFeel& feel) noexcept override;

 private:
  task::Trajectory path_;
  math::Vec3 start_m_;
};

}  // namespace enact::devices
