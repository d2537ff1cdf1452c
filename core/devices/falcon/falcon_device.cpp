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
  if (link_ && !unplugged_.load() && !halted_.load()) link_->send(Command{}, 100);
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
  unplugged_.store(false);
  halted_.store(false);
  active_.store(false);
  force_.store({});
  sample_.store({});
  last_ns_ = 0;
  velocity_m_per_s_ = {};
  seen_writes_ = 0;
  last_write_seen_ns_ = rt::now_ns();
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
  force_.store({{}, force_.load().count});
  active_.store(true);
}

void FalconForceDevice::deactivate() noexcept {
  if (!active_.exchange(false)) return;
  // wait for a zero packet to have gone out (the thread may be gone: unplugged)
  io_.await(zeroed_, zeroed_.load(), kDeactivateWait_ns);
}

bool FalconForceDevice::read(std::int64_t now_ns, ForceSample& out) noexcept {
  const Sample s = sample_.load();
  out.time_ns = s.valid ? s.time_ns : now_ns;
  out.position_m = s.position_m;
  out.velocity_m_per_s = s.velocity_m_per_s;
  out.buttons = s.buttons;
  // unplugged, silent for longer than stale_s, or not active: a device error
  const bool stale = !s.valid || now_ns - s.time_ns > stale_ns_;
  if (!active_.load(std::memory_order_relaxed) || unplugged_.load(std::memory_order_relaxed) || stale) {
    out.velocity_m_per_s = {};
    out.faults = bit(DeviceFault::device_error);
    return false;
  }
  const Vec3& lo = profile_.workspace_min_m;
  const Vec3& hi = profile_.workspace_max_m;
  const Vec3& p = s.position_m;
  const bool inside = p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  out.faults = inside ? 0u : bit(DeviceFault::workspace_limit);
  return true;
}

void FalconForceDevice::write(std::int64_t, const math::Vec3& force_n) noexcept {
  // NaN/Inf: no force (the safety layer above says so in its fault bits)
  const Vec3 f = math::finite(force_n) ? force_n : Vec3{};
  force_.store({f, force_.load().count + 1});
}

Command FalconForceDevice::command(std::int64_t now_ns) noexcept {
  const Force f = force_.load();
  // a loop that stopped writing: zero force after kCommandTimeout_s
  if (f.count != seen_writes_) {
    seen_writes_ = f.count;
    last_write_seen_ns_ = now_ns;
  }
  const bool silent = now_ns - last_write_seen_ns_ > std::llround(kCommandTimeout_s * 1e9);
  Command c{{}, kLedGreen, true};
  if (!active_.load() || silent) return c;
  // clamp, then the transposed Jacobian at the last measured position
  Vec3 force = f.force_n;
  if (const double m = math::norm(force); m > params_.max_force_n) force = force * (params_.max_force_n / m);
  Vec3 tau;
  if (torques(jacobian_, direction_to_device(force), tau)) c.motor = motor_commands(tau);
  return c;
}

bool FalconForceDevice::io_step(std::int64_t now_ns) noexcept {
  if (halted_.load()) return false;
  const Command c = command(now_ns);
  const bool zero = c.motor == std::array<std::int16_t, 3>{};
  Reading r;
  const usb::Status s = link_->exchange(c, r, stale_ns_);
  if (s == usb::Status::no_device) {
    unplugged_.store(true);
    return false;
  }
  if (zero && !active_.load()) zeroed_.fetch_add(1);
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
  sample_.store({now_ns, position, velocity_m_per_s_, r.buttons, true});
  return true;
}

void FalconForceDevice::emergency(void* self) noexcept {
  auto* d = static_cast<FalconForceDevice*>(self);
  d->halted_.store(true);
  if (d->transport_ && !d->unplugged_.load()) d->transport_->emergency_bulk_out(kEndpointOut, d->zero_packet_.data(), kPacketSize);
}

}  // namespace enact::devices::falcon
