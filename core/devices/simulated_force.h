#pragma once
// A simulated force-feedback device: the end-effector is a point mass (the profile's moving
// mass) with the profile's physical damping, pushed by the commanded force and by a hand,
// so a loop closed through it runs through real dynamics. The hand is a spring-damper
// pulling the end-effector towards its target, given by a HandSource (core/devices/hand.h):
// a scripted path (or the start, held), or a virtual subject that reacts to what it feels.
//
// Physics, integrated by semi-implicit Euler in substeps of at most substep_s:
//   m a = F_cmd + k_h (h - x) + c_h (h' - v) - b v + F_stop
//   F_cmd : the command, saturated to the profile's peak force (direction kept)
//   h     : the hand target, from the hand source at the time since the device's clock
//           started, given what the hand feels (handle position, velocity, and the force
//           -(k_h (h - x) + c_h (h' - v)) of the previous substep)
//   F_stop: beyond the profile's workspace, per axis, a push-only spring-damper of
//           stop_stiffness_n_per_m, critically damped for the moving mass
//   |v| is then limited to the profile's max speed (counted in speed_clamps()).
// Reported position: the true position rounded to the nearest multiple of the profile's
// resolution. Reported velocity: the true velocity (as a driver with a velocity estimate
// would give), not the finite difference of quantised positions.
//
// The clock: activate() resets the end-effector to start_m at rest; the first read or write
// after it starts the clock (hand path time 0). A call earlier than the latest one does not
// go back in time. Deterministic: the same calls give the same samples.
#include <cstdint>
#include <string>

#include <memory>

#include "core/devices/device.h"
#include "core/devices/hand.h"

namespace enact::devices {

struct SimulatedForceParams {
  std::string profile = "ergos";          // a device profile name (devices::find_device_profile)
  std::string hand_path;                  // CSV (t_s,x_m,y_m,z_m, t from the clock start) the hand tracks; empty: the hand holds start_m
  std::string subject;                    // a virtual subject's file (YAML) holds the device instead (not with hand_path)
  std::uint64_t subject_seed = 0;         // the virtual subject's traits
  std::uint64_t noise_seed = 0;           // the virtual subject's motor noise and memory errors
  math::Vec3 start_m{0.0, 0.0, 0.0125};  // start position of the end-effector, inside the workspace
  double hand_stiffness_n_per_m = 300.0;  // >= 0 (0 with 0 damping: no hand, a free device)
  double hand_damping_n_s_per_m = 5.0;    // >= 0, on the velocity relative to the target's
  double stop_stiffness_n_per_m = 1e5;    // > 0, the workspace stops
  double substep_s = 1e-4;                // > 0, the longest integration step; bounded for accuracy (configure says)
};

// the params of a device of `profile` whose hand holds it at the enact origin (the handle of
// an emulator)
SimulatedForceParams held_at_origin(const std::string& profile);

class SimulatedForceDevice final : public ForceDevice {
 public:
  explicit SimulatedForceDevice(SimulatedForceParams params = {});

  // find the profile, validate the params, load the hand path or the subject; throws config::Error
  void configure() override;
  // reset the end-effector to start_m at rest, zero force; the next read or write starts the clock
  void activate() override;
  // integrate to now_ns and sample; false (device_error) when not active
  bool read(std::int64_t now_ns, ForceSample& out) noexcept override;
  // integrate to now_ns with the previous force, then apply this one (ignored when not active)
  void write(std::int64_t now_ns, const math::Vec3& force_n) noexcept override;
  // zero force, disable; the state stays where it is
  void deactivate() noexcept override;
  const devices::DeviceProfile& profile() const override { return profile_; }
  // the hand holding the device (valid after configure)
  HandSource* simulated_hand() noexcept override { return hand_.get(); }

  // the unquantised state, for tests and viewers
  math::Vec3 true_position_m() const { return x_m_; }
  math::Vec3 true_velocity_m_per_s() const { return v_m_per_s_; }
  // where the hand pulls the end-effector to, at the device's current time
  math::Vec3 hand_target_m() const { return hand_m_; }
  // the force command acting now (after saturation and NaN rejection)
  math::Vec3 applied_force_n() const { return force_n_; }
  // substeps whose speed was limited to the profile's max speed, since configure
  std::uint64_t speed_clamps() const { return speed_clamps_; }
  // the largest substep_s the current params allow (valid after configure)
  double max_substep_s() const { return max_substep_s_; }
  const SimulatedForceParams& params() const { return params_; }

 private:
  void start_clock(std::int64_t now_ns) noexcept;
  void advance(std::int64_t now_ns) noexcept;
  void substep(std::int64_t to_ns) noexcept;
  void reset_hand() noexcept;
  math::Vec3 stop_force_n() const noexcept;
  bool outside_workspace() const noexcept;

  SimulatedForceParams params_;
  devices::DeviceProfile profile_;
  std::unique_ptr<HandSource> hand_;
  double stop_damping_n_s_per_m_ = 0.0;
  double max_substep_s_ = 0.0;
  std::int64_t substep_ns_ = 0;
  bool configured_ = false;
  bool active_ = false;
  // the clock: started at the first read or write after activate
  bool started_ = false;
  std::int64_t start_ns_ = 0;
  std::int64_t now_ns_ = 0;
  // the state at now_ns_
  math::Vec3 x_m_;
  math::Vec3 v_m_per_s_;
  math::Vec3 hand_m_;
  math::Vec3 hand_force_n_;  // the hand's pull on the handle, last substep
  math::Vec3 force_n_;
  std::uint32_t command_faults_ = 0;  // clamped / nonfinite_command bits of the acting command
  std::uint64_t speed_clamps_ = 0;
};

}  // namespace enact::devices
