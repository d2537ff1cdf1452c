#pragma once
// Device interfaces, with a ros2_control-style lifecycle: configure (open, validate; throws
// config::Error with a fix) -> activate (enable output) -> read / write each tick ->
// deactivate (zero output, disable). read, write and shown take the time they act at (int64
// ns of a monotonic clock), allocate nothing and never throw: faults are reported in the
// sample and counted, never thrown through the loop.
#include <array>
#include <cstdint>

#include "core/devices/device_profile.h"
#include "core/math/vec3.h"

namespace enact::devices {

class HandSource;

// fault bits of a ForceSample: each set while the condition holds at the sample's time
enum class DeviceFault : std::uint32_t {
  watchdog = 1u << 0,           // no force command within the watchdog time: force ramps to zero
  clamped = 1u << 1,            // the force acting was limited to the device's peak force
  nonfinite_command = 1u << 2,  // the force command was NaN or Inf: zero force acts instead
  workspace_limit = 1u << 3,    // the end-effector is outside the workspace, against a stop
  device_error = 1u << 4,       // the device could not be read (or is not active)
};

// the bit of one fault in a faults word
constexpr std::uint32_t bit(DeviceFault fault) { return static_cast<std::uint32_t>(fault); }
// whether a faults word has that fault's bit
constexpr bool has(std::uint32_t faults, DeviceFault fault) { return (faults & bit(fault)) != 0; }
// the fault's name ("watchdog", ...)
const char* to_string(DeviceFault fault);

// the state of a force-feedback device at one time
struct ForceSample {
  std::int64_t time_ns = 0;
  math::Vec3 position_m;
  math::Vec3 velocity_m_per_s;
  std::uint32_t buttons = 0;  // bit i: button i pressed
  std::uint32_t faults = 0;   // DeviceFault bits
  math::Vec3 force_n;         // the force acting on the hand now (N): set by the safety layer
};

// a force-feedback device (FFD): reads the end-effector, applies a force to it
class ForceDevice {
 public:
  virtual ~ForceDevice();
  // open the device and validate its parameters; throws config::Error (problem and fix)
  virtual void configure() = 0;
  // enable output with zero force
  virtual void activate() = 0;
  // the device's state at now_ns into out; false on a device error (out.faults says which)
  virtual bool read(std::int64_t now_ns, ForceSample& out) noexcept = 0;
  // the force (N) applied from now_ns on
  virtual void write(std::int64_t now_ns, const math::Vec3& force_n) noexcept = 0;
  // zero the force, then disable output
  virtual void deactivate() noexcept = 0;
  // what the device can do (valid after configure)
  virtual const devices::DeviceProfile& profile() const = 0;
  // the simulated hand holding a simulated device (core/devices/hand.h); nullptr for a real
  // device, which a person holds
  virtual HandSource* simulated_hand() noexcept { return nullptr; }
};

// The motion of up to 32 pins: each moves linearly towards its target (up = 1, down = 0) at
// 1 / rise_ns per ns, from the level it had when its target last changed, so a full stroke
// takes rise_ns and a target changed mid-stroke reverses from the level reached. Trivially
// copyable (it crosses threads by copy); allocates nothing.
struct PinMotion {
  // a pin's stroke: from a level at a time, towards its target
  struct Stroke {
    double from_level = 0.0;
    std::int64_t from_ns = 0;
  };
  std::array<Stroke, 32> strokes{};
  std::uint32_t targets = 0;  // bit i = pin i up
  double rise_ns = 24e6;      // > 0, the time of a full stroke

  // pin i's level at now_ns, 0 .. 1 (not before the pin's last target change)
  double level(int pin, std::int64_t now_ns) const noexcept;
  // new targets from now_ns on for pins 0 .. count: a pin whose target changes starts a new
  // stroke from the level it has reached
  void set_targets(std::int64_t now_ns, std::uint32_t pins, int count) noexcept;
};

// a tactile pin array: rows x cols pins, pin i = row * cols + col, at most 32 pins
class TactileDevice {
 public:
  virtual ~TactileDevice();
  // open the device and validate its parameters; throws config::Error (problem and fix)
  virtual void configure() = 0;
  // enable output with every pin down
  virtual void activate() = 0;
  // the target from now_ns on: bit i set = pin i up
  virtual void write(std::int64_t now_ns, std::uint32_t pins) noexcept = 0;
  // what the pins physically show at now_ns, 0 = down .. 1 = up, into levels[0 .. count)
  // (pins beyond count are not written; levels beyond rows * cols are left untouched)
  virtual void shown(std::int64_t now_ns, float* levels, int count) noexcept = 0;
  // the pins' motion from the last write on, where the device knows it (simulated cells, the
  // Metec driver's estimate): shown(t) is out.level(i, t) for any t until the next write, on
  // the clock shown() takes. false: the device knows only shown()
  virtual bool motion(PinMotion& out) const noexcept {
    (void)out;
    return false;
  }
  virtual int rows() const = 0;
  virtual int cols() const = 0;
  // lower every pin, then disable output
  virtual void deactivate() noexcept = 0;
};

}  // namespace enact::devices
