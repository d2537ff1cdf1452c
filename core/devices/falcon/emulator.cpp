#include "core/devices/falcon/emulator.h"

#include <algorithm>

#include "core/rt/clock.h"

namespace enact::devices::falcon {
namespace {

// what the FT232 puts before the data of every read (modem status: CTS, DSR; line status: THRE, TEMT)
constexpr std::uint8_t kModemStatus = 0x31;
constexpr std::uint8_t kLineStatus = 0x60;
// a wrong answer of the boot loader to the check message
constexpr std::array<std::uint8_t, 4> kWrongReply = {0x0A, 0x45, 0x2C, 0x0D};
// the device-frame point whose arm angles are the homing index ("all the way in")
constexpr Vec3 kIndexPoint_device{0.0, 0.0, 0.075};

}  // namespace

SimulatedForceParams FalconEmulatorParams::default_grip() { return held_at_origin("falcon"); }

double FalconEmulator::index_angle() {
  static const double angle = [] {
    LegAngles a;
    inverse(kIndexPoint_device, a);
    return a.t1[0];  // the same for the three arms on the z axis
  }();
  return angle;
}

FalconEmulator::FalconEmulator(FalconEmulatorParams params) : params_(std::move(params)), grip_(params_.grip) {
  grip_.configure();
  grip_.activate();
  mode_ = params_.firmware_running ? Mode::running : Mode::off;
  handshake_failures_left_ = params_.handshake_failures;
  homed_ = params_.homed ? kAllHomed : 0;
  // the arms where the grip starts; un-homed encoders count 0 there
  inverse(to_device(params_.grip.start_m), angles_);
  for (std::size_t i = 0; i < 3; ++i) count_offset_[i] = params_.homed ? 0 : static_cast<std::int16_t>(-count_of(angles_.t1[i]));
}

std::int64_t FalconEmulator::now() const { return params_.clock ? params_.clock() : rt::now_ns(); }

usb::Outcome FalconEmulator::control(const usb::ControlSetup& setup, std::uint8_t*, std::uint16_t) {
  if (setup.request_type != usb::kVendorOut) return {usb::Status::stall, 0};
  std::lock_guard lock(mutex_);
  control_locked(setup);
  return {usb::Status::ok, 0};
}

void FalconEmulator::control_locked(const usb::ControlSetup& s) {
  switch (s.request) {
    case ftdi::kReset:
      if (s.value == ftdi::kPurgeRx) to_host_.clear();
      if (s.value == ftdi::kPurgeTx) from_host_.clear();
      break;
    case ftdi::kModemControl:
      if (s.value & ftdi::kDtrLow) {
        const bool dtr = (s.value & 0x01) != 0;
        // a rising DTR resets the DSP into its boot loader: the firmware is gone
        if (dtr && !dtr_) {
          mode_ = Mode::boot_check;
          checked_ = false;
          firmware_.clear();
          from_host_.clear();
        }
        dtr_ = dtr;
      }
      break;
    case ftdi::kBaudRate:
      baud_ = s.value;
      // the boot loader passed its check and DTR is low: it waits for the boot byte
      if (mode_ == Mode::boot_check && baud_ == ftdi::kBaudBoot && !dtr_ && checked_) mode_ = Mode::boot_wait;
      // the uploaded firmware starts at the running rate
      if (mode_ == Mode::boot_upload && baud_ == ftdi::kBaudRun && !firmware_.empty()) {
        mode_ = Mode::running;
        packets_in_.clear();
      }
      break;
    default: break;  // flow control, line settings, latency timer: nothing to emulate
  }
}

usb::Outcome FalconEmulator::out(std::uint8_t endpoint, const std::uint8_t* data, int length) {
  if (endpoint != kEndpointOut) return {usb::Status::stall, 0};
  std::lock_guard lock(mutex_);
  receive_locked(data, length);
  return {usb::Status::ok, length};
}

void FalconEmulator::receive_locked(const std::uint8_t* data, int length) {
  switch (mode_) {
    case Mode::off: break;  // no firmware: nothing answers
    case Mode::boot_check: {
      // the check message, answered right after the configured failures
      if (checked_) break;
      from_host_.insert(from_host_.end(), data, data + length);
      if (from_host_.size() < kCheckRequest.size()) break;
      const bool is_check = std::equal(kCheckRequest.begin(), kCheckRequest.end(), from_host_.end() - static_cast<std::ptrdiff_t>(kCheckRequest.size()));
      from_host_.clear();
      if (!is_check) break;
      ++check_messages_;
      if (handshake_failures_left_ > 0) {
        --handshake_failures_left_;
        queue_locked(kWrongReply.data(), static_cast<int>(kWrongReply.size()));
      } else {
        queue_locked(kCheckReply.data(), static_cast<int>(kCheckReply.size()));
        checked_ = true;
      }
      break;
    }
    case Mode::boot_wait:
      if (length > 0 && data[0] == kBootByte) {
        queue_locked(&kBootByte, 1);
        mode_ = Mode::boot_upload;
      }
      break;
    case Mode::boot_upload:
      // every byte of the firmware is echoed
      firmware_.insert(firmware_.end(), data, data + length);
      queue_locked(data, length);
      break;
    case Mode::running: {
      packets_in_.feed(data, length);
      Packet p;
      while (packets_in_.next(p)) {
        Command c;
        if (decode(p, c)) answer_locked(c);
      }
      break;
    }
  }
}

void FalconEmulator::answer_locked(const Command& c) {
  const std::int64_t t = now();
  // the grip at this time, and the arms' angles there (held when out of reach)
  ForceSample s;
  grip_.read(t, s);
  LegAngles a;
  if (inverse(to_device(grip_.true_position_m()), a)) angles_ = a;
  // homing: an arm passing its index in homing mode is homed
  Reading r;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto bit = static_cast<std::uint8_t>(1u << i);
    if (c.homing && !(homed_ & bit) && angles_.t1[i] <= index_angle()) {
      homed_ |= bit;
      count_offset_[i] = 0;
    }
    r.encoder[i] = static_cast<std::int16_t>(count_of(angles_.t1[i]) + count_offset_[i]);
  }
  r.homed = c.homing ? homed_ : 0;
  r.buttons = buttons_;
  // the motors: commands -> joint torques -> the force on the grip
  motor_force_n_ = direction_to_enact(force_of(angle_jacobian(angles_), torques_of(c.motor)));
  grip_.write(t, motor_force_n_);
  last_command_ = c;
  ++packets_;
  const Packet p = encode(r);
  queue_locked(p.data(), kPacketSize);
}

void FalconEmulator::queue_locked(const std::uint8_t* data, int n) { to_host_.insert(to_host_.end(), data, data + n); }

usb::Outcome FalconEmulator::in(std::uint8_t endpoint, std::uint8_t* data, int length) {
  if (endpoint != kEndpointIn) return {usb::Status::stall, 0};
  if (length < kStatusBytes) return {usb::Status::io, 0};
  std::lock_guard lock(mutex_);
  // the status bytes, then what is waiting (at most a full-speed packet)
  data[0] = kModemStatus;
  data[1] = kLineStatus;
  const int n = std::min({static_cast<int>(to_host_.size()), length - kStatusBytes, kReadSize - kStatusBytes});
  std::copy_n(to_host_.begin(), n, data + kStatusBytes);
  to_host_.erase(to_host_.begin(), to_host_.begin() + n);
  return {usb::Status::ok, kStatusBytes + n};
}

bool FalconEmulator::running() const {
  std::lock_guard lock(mutex_);
  return mode_ == Mode::running;
}

std::vector<std::uint8_t> FalconEmulator::firmware() const {
  std::lock_guard lock(mutex_);
  return firmware_;
}

int FalconEmulator::check_messages() const {
  std::lock_guard lock(mutex_);
  return check_messages_;
}

std::uint64_t FalconEmulator::packets() const {
  std::lock_guard lock(mutex_);
  return packets_;
}

Command FalconEmulator::last_command() const {
  std::lock_guard lock(mutex_);
  return last_command_;
}

std::uint8_t FalconEmulator::homed() const {
  std::lock_guard lock(mutex_);
  return homed_;
}

Vec3 FalconEmulator::grip_position_m() const {
  std::lock_guard lock(mutex_);
  return grip_.true_position_m();
}

Vec3 FalconEmulator::motor_force_n() const {
  std::lock_guard lock(mutex_);
  return motor_force_n_;
}

void FalconEmulator::press(std::uint8_t buttons) {
  std::lock_guard lock(mutex_);
  buttons_ = buttons;
}

}  // namespace enact::devices::falcon
