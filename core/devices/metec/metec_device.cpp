#include "core/devices/metec/metec_device.h"

#include <algorithm>
#include <cmath>

#include "core/devices/params_error.h"
#include "core/rt/clock.h"

namespace enact::devices::metec {
namespace {

constexpr const char* kDevice = "metec";
constexpr int kSetupTimeout_ms = 1000;
constexpr int kIdentityTimeout_ms = 200;
constexpr std::int64_t kWait_ns = 200'000'000;  // at most: activate / deactivate wait for the I/O thread

}  // namespace

MetecTactileDevice::MetecTactileDevice(MetecParams params, std::unique_ptr<usb::Bus> bus) : params_(std::move(params)), bus_(std::move(bus)) {}

MetecTactileDevice::~MetecTactileDevice() {
  io_.stop();
  // pins down, high voltage off, unless the display is gone or already off
  if (transport_ && !unplugged_.load() && !halted_.load() && high_voltage_) {
    write_modules(0, false);
    set_high_voltage(false);
  }
  emergency_.reset();
  transport_.reset();
}

void MetecTactileDevice::validate() const {
  const MetecParams& p = params_;
  require(p.rows >= 1 && p.rows <= 4, kDevice, "rows", p.rows, "1 .. 4 (a cell has 4 dot rows)");
  require(p.cols >= 1 && p.cols <= 8, kDevice, "cols", p.cols, "1 .. 8 (two pin columns per cell, up to 4 cells: 32 pins)");
  require(p.first_cell >= 0 && p.first_cell < kMaxModules * kCellsPerModule, kDevice, "first_cell", p.first_cell, "0 .. 79");
  require(std::isfinite(p.rise_time_s) && p.rise_time_s > 0.0, kDevice, "rise_time_s", p.rise_time_s, "(0, ...) s (Metec: 0.024)");
  require(std::isfinite(p.io_period_s) && p.io_period_s > 0.0 && p.io_period_s <= 0.05, kDevice, "io_period_s", p.io_period_s, "(0, 0.05] s (default 0.001)");
  require(std::isfinite(p.status_period_s) && p.status_period_s > 0.0 && p.status_period_s <= 1.0, kDevice, "status_period_s", p.status_period_s, "(0, 1] s (default 0.05)");
  require(p.timeout_ms >= 1 && p.timeout_ms <= 1000, kDevice, "timeout_ms", p.timeout_ms, "1 .. 1000 (default 20)");
}

void MetecTactileDevice::configure() {
  io_.stop();
  configured_ = false;
  validate();
  layout_ = {params_.rows, params_.cols, params_.first_cell};
  mask_ = layout_.pins() == 32 ? ~0u : (1u << layout_.pins()) - 1u;
  // the display
  transport_ = usb::open_device(*bus_, kDevice, params_.serial, {kConfiguration, kInterface});
  // its identity (BRLTTY logs it; the text comes on the input endpoint)
  std::uint8_t zero = 0;
  identity_.clear();
  if (transport_->control({usb::kVendorOut, kIdentify, 0, 0}, &zero, 1, kSetupTimeout_ms).ok()) {
    std::array<std::uint8_t, kIdentitySize> text{};
    const usb::Outcome o = transport_->bulk(kEndpointIn, text.data(), kIdentitySize, kIdentityTimeout_ms);
    if (o.bytes > 0) identity_.assign(reinterpret_cast<const char*>(text.data()), static_cast<std::size_t>(o.bytes));
  }
  // its cells: the pins must fit
  std::array<std::uint8_t, kStatusSize> status{};
  const usb::Outcome o = transport_->control({usb::kVendorIn, kGetStatus, 0, 0}, status.data(), kStatusSize, kSetupTimeout_ms);
  if (!o.ok() || o.bytes != kStatusSize) {
    refuse(kDevice, std::string("the display did not answer its status request: ") + usb::to_string(o.status), "unplug and replug it, then try again");
  }
  display_cells_ = decode_status(status).cells;
  const int last = layout_.first_cell + layout_.cells() - 1;
  if (last >= display_cells_) {
    refuse(kDevice,
           std::to_string(params_.rows) + " x " + std::to_string(params_.cols) + " pins need cells " + std::to_string(layout_.first_cell) + " .. " +
               std::to_string(last) + ", the display has " + std::to_string(display_cells_),
           "set first_cell to 0 .. " + std::to_string(std::max(0, display_cells_ - layout_.cells())) + " or use fewer columns");
  }
  // the I/O thread, high voltage off until activate
  high_voltage_ = false;
  faulted_.store(false);
  unplugged_.store(false);
  halted_.store(false);
  active_.store(false);
  target_.store(0);
  shown_ = {};
  shown_.rise_ns = params_.rise_time_s * 1e9;
  motion_.store(shown_);
  for (auto& m : written_) m.fill(0);
  next_status_ns_ = 0;
  emergency_ = usb::EmergencyStop(&MetecTactileDevice::emergency, this);
  io_.start(std::llround(params_.io_period_s * 1e9), [this](std::int64_t now) { return io_step(now); });
  configured_ = true;
}

void MetecTactileDevice::activate() {
  if (!configured_) refuse(kDevice, "activate before configure", "call configure() first");
  if (faulted_.load()) refuse(kDevice, "the display faulted (pins lowered, high voltage off)", "configure it again");
  target_.store(0);
  const std::uint64_t before = switched_on_.load();
  active_.store(true);
  io_.await(switched_on_, before, kWait_ns);
}

void MetecTactileDevice::deactivate() noexcept {
  if (!active_.exchange(false)) return;
  io_.await(switched_off_, switched_off_.load(), kWait_ns);
}

void MetecTactileDevice::write(std::int64_t, std::uint32_t pins) noexcept { target_.store(pins & mask_, std::memory_order_relaxed); }

void MetecTactileDevice::shown(std::int64_t now_ns, float* levels, int count) noexcept {
  const PinMotion m = motion_.load();
  const int n = std::min(count, layout_.pins());
  for (int i = 0; i < n; ++i) levels[i] = static_cast<float>(m.level(i, now_ns));
}

bool MetecTactileDevice::motion(PinMotion& out) const noexcept {
  out = motion_.load();
  return true;
}

std::int64_t MetecTactileDevice::now() const noexcept { return params_.clock ? params_.clock() : rt::now_ns(); }

bool MetecTactileDevice::write_modules(std::uint32_t pins, bool all) noexcept {
  // the pins' cells, placed in their modules
  std::array<std::uint8_t, 8> cells{};
  cells_of(layout_, pins, cells.data());
  for (int module = layout_.first_module(); module <= layout_.last_module(); ++module) {
    std::array<std::uint8_t, kCellsPerModule> bytes{};
    for (int k = 0; k < layout_.cells(); ++k) {
      const int cell = layout_.first_cell + k;
      if (cell / kCellsPerModule == module) bytes[static_cast<std::size_t>(cell % kCellsPerModule)] = cells[static_cast<std::size_t>(k)];
    }
    // only modules whose cells changed
    auto& before = written_[static_cast<std::size_t>(module)];
    if (!all && bytes == before) continue;
    const usb::Outcome o =
        transport_->control({usb::kVendorOut, static_cast<std::uint8_t>(kWriteModule + module), 0, 0}, bytes.data(), kCellsPerModule, params_.timeout_ms);
    if (!o.ok()) {
      fault(o.status);
      return false;
    }
    before = bytes;
    module_writes_.fetch_add(1);
  }
  // the cells take it now: they start moving
  if (high_voltage_) shown_.set_targets(now(), pins, layout_.pins());
  motion_.store(shown_);
  return true;
}

bool MetecTactileDevice::set_high_voltage(bool on) noexcept {
  std::uint8_t value = on ? kHighVoltageOn : kHighVoltageOff;
  const usb::Outcome o = transport_->control({usb::kVendorOut, kSetHighVoltage, 0, 0}, &value, 1, params_.timeout_ms);
  if (!o.ok()) {
    fault(o.status);
    return false;
  }
  high_voltage_ = on;
  // with the high voltage off every pin drops
  if (!on) shown_.set_targets(now(), 0, layout_.pins());
  motion_.store(shown_);
  return true;
}

// a fault: high voltage off (tried; the display may be gone), pins shown falling from now,
// and then it is said (faulted() true means all of that is done)
void MetecTactileDevice::fault(usb::Status status) noexcept {
  const bool gone = status == usb::Status::no_device;
  if (!gone) {
    std::uint8_t off = kHighVoltageOff;
    transport_->control({usb::kVendorOut, kSetHighVoltage, 0, 0}, &off, 1, params_.timeout_ms);
  }
  high_voltage_ = false;
  shown_.set_targets(now(), 0, layout_.pins());
  motion_.store(shown_);
  unplugged_.store(gone);
  faulted_.store(true);
}

bool MetecTactileDevice::io_step(std::int64_t now_ns) noexcept {
  if (halted_.load() || faulted_.load()) return false;
  const bool active = active_.load();
  // switched on: pins down first, then the high voltage
  if (active && !high_voltage_) {
    if (!write_modules(0, true) || !set_high_voltage(true)) return false;
    switched_on_.fetch_add(1);
  }
  // switched off: pins lowered, then the high voltage off
  if (!active && high_voltage_) {
    if (!write_modules(0, false)) return false;
    set_high_voltage(false);
    switched_off_.fetch_add(1);
  }
  if (active && !write_modules(target_.load(), false)) return false;
  // now and then, the status: a display that stopped answering is a fault
  if (now_ns >= next_status_ns_) {
    next_status_ns_ = now_ns + std::llround(params_.status_period_s * 1e9);
    std::array<std::uint8_t, kStatusSize> status{};
    const usb::Outcome o = transport_->control({usb::kVendorIn, kGetStatus, 0, 0}, status.data(), kStatusSize, params_.timeout_ms);
    if (!o.ok()) {
      fault(o.status);
      return false;
    }
  }
  return true;
}

void MetecTactileDevice::emergency(void* self) noexcept {
  auto* d = static_cast<MetecTactileDevice*>(self);
  d->halted_.store(true);
  const std::uint8_t off = kHighVoltageOff;
  if (d->transport_ && !d->unplugged_.load()) d->transport_->emergency_control_out({usb::kVendorOut, kSetHighVoltage, 0, 0}, &off, 1);
}

}  // namespace enact::devices::metec
