#include "core/devices/falcon/falcon_device.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "core/config/format.h"
#include "core/devices/params_error.h"
#include "core/rt/clock.h"

namespace enact::devices::falcon {
namespace {

constexpr const char* kDevice = "falcon";
constexpr std::int64_t kProbeTimeout_ns = 20'000'000;     // an answer to a probe packet
constexpr int kProbes = 5;                                 // probe packets before deciding no firmware runs
constexpr std::int64_t kHomingExchange_ns = 20'000'000;    // an answer while homing
constexpr std::int64_t kDeactivateWait_ns = 200'000'000;   // at most, for the zero packet to go out
constexpr double kVelocityTimeConstant_s = 0.005;          // the velocity estimate's low-pass

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse(kDevice, "cannot read the firmware file '" + path + "'", "set firmware to the Falcon firmware file (enact does not ship it)");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) refuse(kDevice, "the firmware file '" + path + "' is empty", "set firmware to the Falcon firmware file");
  return bytes;
}

}  // namespace

FalconForceDevice::FalconForceDevice(FalconParams params, std::unique_ptr<usb::Bus> bus) : params_(std::move(params)), bus_(std::move(bus)) {}

FalconForceDevice::~FalconForceDevice() {
  io_.stop();
  // last words: zero force, LEDs off
  if (link_ && !exchange_.failed() && !halted_.load()) link_->send(Command{}, 100);
  emergency_.reset();
  link_.reset();
  transport_.reset();
}

void FalconForceDevice::validate() const {
  const FalconParams& p = params_;
  require(p.firmware_attempts >= 1, kDevice, "firmware_attempts", p.firmware_attempts, "1 .. (default 5)");
  require(p.handshake_tries >= 1, kDevice, "handshake_tries", p.handshake_tries, "1 .. (default 20)");
  require(std::isfinite(p.homing_timeout_s) && p.homing_timeout_s > 0.0, kDevice, "homing_timeout_s", p.homing_timeout_s, "(0, ...) s (default 60)");
  require(std::isfinite(p.max_force_n) && p.max_force_n > 0.0 && p.max_force_n <= 9.0, kDevice, "max_force_n", p.max_force_n, "(0, 9] N (default 8)");
  require(std::isfinite(p.stale_s) && p.stale_s > 0.0 && p.stale_s <= 0.009, kDevice, "stale_s", p.stale_s, "(0, 0.009] s: faults must show within 10 ms (default 0.005)");
  require(std::isfinite(p.io_period_s) && p.io_period_s > 0.0 && p.io_period_s <= 0.01, kDevice, "io_period_s", p.io_period_s, "(0, 0.01] s (default 0.001)");
}

void FalconForceDevice::configure() {
  io_.stop();
  configured_ = false;
  validate();
  profile_ = *devices::find_device_profile("falcon");
  profile_.peak_force_n = params_.max_force_n;
  stale_ns_ = std::llround(params_.stale_s * 1e9);
  zero_packet_ = encode(Command{});
  // the device
  link_.reset();
  transport_ = usb::open_device(*bus_, kDevice, params_.serial, {-1, kInterface});
  link_ = std::make_unique<Link>(*transport_);
  std::string why;
  if (!link_->enter_normal_mode(why)) refuse(kDevice, "cannot set up the Falcon's FT232: " + why, "unplug and replug the Falcon, then try again");
  // its firmware: running already (loaded earlier in this power cycle), or uploaded now
  uploaded_ = false;
  if (!probe(*link_)) load_firmware(*link_);
  home(*link_);
  // the I/O thread, zero force until activate
  halted_.store(false);
  exchange_.reset(stale_ns_, std::llround(kCommandTimeout_s * 1e9), rt::now_ns());
  last_ns_ = 0;
  velocity_m_per_s_ = {};
  emergency_ = usb::EmergencyStop(&FalconForceDevice::emergency, this);
  io_.start(std::llround(params_.io_period_s * 1e9), [this](std::int64_t now) { return io_step(now); });
  configured_ = true;
}

bool FalconForceDevice::probe(Link& link) {
  for (int i = 0; i < kProbes; ++i) {
    Reading r;
    const usb::Status s = link.exchange(Command{}, r, kProbeTimeout_ns);
    if (s == usb::Status::ok) return true;
    if (s == usb::Status::no_device) refuse(kDevice, "the Falcon was unplugged", "plug it back in and start again");
  }
  return false;
}

void FalconForceDevice::load_firmware(Link& link) {
  if (params_.firmware.empty()) {
    refuse(kDevice, "the Falcon's firmware is not running (it must be uploaded at every power-up)",
           "set firmware to the Falcon firmware file: enact does not ship it (Novint's driver package and libnifalcon's sources have it)");
  }
  const std::vector<std::uint8_t> firmware = read_bytes(params_.firmware);
  std::string why;
  for (int attempt = 1; attempt <= params_.firmware_attempts; ++attempt) {
    if (link.enter_boot_loader(params_.handshake_tries, why) && link.upload(firmware, why) && link.enter_normal_mode(why) && probe(link)) {
      uploaded_ = true;
      return;
    }
    if (link.last_error() == usb::Status::no_device) refuse(kDevice, "the Falcon was unplugged during the firmware upload", "plug it back in and start again");
    if (why.empty()) why = "the firmware did not answer after the upload";
  }
  refuse(kDevice, "the firmware upload failed " + std::to_string(params_.firmware_attempts) + " times; last: " + why,
         "check the Falcon's power supply, unplug and replug it, check that '" + params_.firmware + "' is the Falcon firmware; or raise firmware_attempts");
}

void FalconForceDevice::home(Link& link) {
  const std::int64_t give_up = rt::now_ns() + std::llround(params_.homing_timeout_s * 1e9);
  bool told = false;
  Reading r;
  while (true) {
    const usb::Status s = link.exchange({{}, kLedRed, true}, r, kHomingExchange_ns);
    if (s == usb::Status::no_device) refuse(kDevice, "the Falcon was unplugged while homing", "plug it back in and start again");
    if (s == usb::Status::ok && r.homed == kAllHomed) break;
    if (rt::now_ns() > give_up) {
      refuse(kDevice, "the Falcon did not home within " + config::number(params_.homing_timeout_s) + " s",
             "move the grip all the way out, then push it straight all the way in (the LED turns from red to green); or raise homing_timeout_s");
    }
    if (!told && s == usb::Status::ok) {
      std::fprintf(stderr, "falcon: not homed: move the grip all the way out, then push it straight all the way in (the LED turns green)\n");
      told = true;
    }
  }
  // the first position, the forward kinematics' starting point from then on
  const std::array<double, 3> t1{angle_of(r.encoder[0]), angle_of(r.encoder[1]), angle_of(r.encoder[2])};
  if (!forward(t1, {0.0, 0.0, kCentreZ_m}, device_position_m_)) {
    refuse(kDevice, "the Falcon's encoders give no position", "home it again: unplug its power, plug it back, and move the grip out and in");
  }
  LegAngles a;
  inverse(device_position_m_, a);
  jacobian_ = angle_jacobian(a);
  link.exchange({{}, kLedGreen, true}, r, kHomingExchange_ns);
}

void FalconForceDevice::activate() {
  if (!configured_) refuse(kDevice, "activate before configure", "call configure() first");
  exchange_.set_active(true);
}

void FalconForceDevice::deactivate() noexcept {
  if (!exchange_.active()) return;
  // wait for a zero packet to have gone out (the thread may be gone: unplugged)
  exchange_.set_active(false);
  exchange_.await_zero(kDeactivateWait_ns);
}

bool FalconForceDevice::read(std::int64_t now_ns, ForceSample& out) noexcept { return exchange_.read(now_ns, profile_, out); }

// NaN/Inf: no force (the safety layer above says so in its fault bits)
void FalconForceDevice::write(std::int64_t, const math::Vec3& force_n) noexcept { exchange_.write(force_n); }

Command FalconForceDevice::command(std::int64_t now_ns) noexcept {
  // zero when inactive, or when the loop stopped writing (kCommandTimeout_s)
  Vec3 force = exchange_.command(now_ns);
  Command c{{}, kLedGreen, true};
  // clamp, then the transposed Jacobian at the last measured position
  if (const double m = math::norm(force); m > params_.max_force_n) force = force * (params_.max_force_n / m);
  Vec3 tau;
  if (torques(jacobian_, direction_to_device(force), tau)) c.motor = motor_commands(tau);
  return c;
}

bool FalconForceDevice::io_step(std::int64_t now_ns) noexcept {
  if (halted_.load()) return false;
  const Command c = command(now_ns);
  Reading r;
  const usb::Status s = link_->exchange(c, r, stale_ns_);
  if (s == usb::Status::no_device) {
    exchange_.fail();
    return false;
  }
  if (s != usb::Status::ok || !take(r, rt::now_ns())) {
    missed_.fetch_add(1);
    return true;
  }
  exchanges_.fetch_add(1);
  return true;
}

bool FalconForceDevice::take(const Reading& r, std::int64_t now_ns) noexcept {
  // encoders -> arm angles -> position (warm-started Newton), and the Jacobian there
  const std::array<double, 3> t1{angle_of(r.encoder[0]), angle_of(r.encoder[1]), angle_of(r.encoder[2])};
  Vec3 p;
  LegAngles a;
  if (!forward(t1, device_position_m_, p) || !inverse(p, a)) return false;
  jacobian_ = angle_jacobian(a);
  // velocity: finite difference, low-passed
  const Vec3 previous = to_enact(device_position_m_);
  const Vec3 position = to_enact(p);
  if (last_ns_ > 0 && now_ns > last_ns_) {
    const double dt = static_cast<double>(now_ns - last_ns_) * 1e-9;
    const double alpha = dt / (kVelocityTimeConstant_s + dt);
    velocity_m_per_s_ += ((position - previous) * (1.0 / dt) - velocity_m_per_s_) * alpha;
  }
  device_position_m_ = p;
  last_ns_ = now_ns;
  exchange_.publish({now_ns, position, velocity_m_per_s_, r.buttons, true});
  return true;
}

void FalconForceDevice::emergency(void* self) noexcept {
  auto* d = static_cast<FalconForceDevice*>(self);
  d->halted_.store(true);
  if (d->transport_ && !d->exchange_.failed()) d->transport_->emergency_bulk_out(kEndpointOut, d->zero_packet_.data(), kPacketSize);
}

}  // namespace enact::devices::falcon
