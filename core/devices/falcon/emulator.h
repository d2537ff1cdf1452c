#pragma once
// An emulated Novint Falcon at the packet level, for a fake USB transport (usb/fake.h): the
// FT232's vendor requests and status bytes, the boot loader (check message, boot byte,
// firmware echoed chunk by chunk), and the running firmware's lock-step packets.
//
// The grip is a simulated device (simulated_force.h, the "falcon" profile: its mass,
// damping, workspace stops, and a scripted hand pulling it along a path). Every packet
// steps it to the clock's time: the motor commands become joint torques (libnifalcon's
// scale), the torques the force on the grip through the kinematics (F = J^T tau), and the
// grip's position the encoder counts through the inverse kinematics, quantised like the
// real encoders. So the backend above is driven through its whole path: protocol,
// kinematics both ways, homing.
//
// Modelled, not measured (no real Falcon was available): a DTR low-to-high edge resets the
// DSP into its boot loader; the running firmware answers only whole valid packets; the
// encoders are incremental: until homed they count from wherever the arms were at power-up;
// in homing mode an arm is homed when it passes its index, the angle it has with the grip
// pushed all the way in (z = 0.075 m in the device frame, 35 mm in from the centre).
#include <cstdint>
#include <mutex>
#include <vector>

#include "core/devices/falcon/kinematics.h"
#include "core/devices/falcon/protocol.h"
#include "core/devices/simulated_force.h"
#include "core/devices/usb/fake.h"
#include "core/rt/clock.h"

namespace enact::devices::falcon {

struct FalconEmulatorParams {
  SimulatedForceParams grip = default_grip();  // the grip's dynamics and the scripted hand
  bool firmware_running = true;  // false: in the boot loader, as at power-up: the host must upload
  bool homed = true;             // false: the encoders must be homed first
  int handshake_failures = 0;    // check messages answered wrongly before the first right one
  rt::ClockFn clock = nullptr;  // monotonic ns; null: CLOCK_MONOTONIC

  // the "falcon" profile, the hand holding the grip at the workspace centre
  static SimulatedForceParams default_grip();
};

class FalconEmulator final : public usb::Emulator {
 public:
  // configures the grip (throws config::Error on bad grip params)
  explicit FalconEmulator(FalconEmulatorParams params = {});

  usb::Outcome control(const usb::ControlSetup& setup, std::uint8_t* data, std::uint16_t length) override;
  usb::Outcome out(std::uint8_t endpoint, const std::uint8_t* data, int length) override;
  usb::Outcome in(std::uint8_t endpoint, std::uint8_t* data, int length) override;

  // what a test reads (each call locks)
  bool running() const;                       // the firmware runs
  std::vector<std::uint8_t> firmware() const;  // what was uploaded
  int check_messages() const;                  // check messages received
  std::uint64_t packets() const;               // lock-step packets answered
  Command last_command() const;                // the last valid command received
  std::uint8_t homed() const;                  // bit i: arm i homed
  Vec3 grip_position_m() const;                // the grip's true position (enact frame)
  Vec3 motor_force_n() const;                  // the force the motors put on the grip (enact frame)
  // grip buttons reported from now on (bit i: button i)
  void press(std::uint8_t buttons);

  // the index angle of the arms (rad): passing it in homing mode homes an arm
  static double index_angle();

 private:
  enum class Mode { off, boot_check, boot_wait, boot_upload, running };
  void control_locked(const usb::ControlSetup& s);
  void receive_locked(const std::uint8_t* data, int length);
  void answer_locked(const Command& c);
  void queue_locked(const std::uint8_t* data, int n);
  std::int64_t now() const;

  mutable std::mutex mutex_;
  FalconEmulatorParams params_;
  SimulatedForceDevice grip_;
  Mode mode_ = Mode::off;
  // the FT232
  std::uint16_t baud_ = 0;
  bool dtr_ = false;
  std::vector<std::uint8_t> to_host_;   // bytes waiting for a bulk IN
  std::vector<std::uint8_t> from_host_; // a check message being received
  // the DSP
  std::vector<std::uint8_t> firmware_;
  bool checked_ = false;  // the check message was answered right
  int handshake_failures_left_ = 0;
  int check_messages_ = 0;
  PacketReader packets_in_;
  std::uint64_t packets_ = 0;
  Command last_command_;
  std::uint8_t homed_ = 0;
  std::array<std::int16_t, 3> count_offset_{};  // encoder count minus the true count until homed
  LegAngles angles_;                             // the arms at the last packet
  Vec3 motor_force_n_;
  std::uint8_t buttons_ = 0;
};

}  // namespace enact::devices::falcon
