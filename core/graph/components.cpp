#include "core/graph/components.h"

#include "core/config/yaml.h"
#include "core/devices/falcon/emulator.h"
#include "core/devices/falcon/falcon_device.h"
#include "core/devices/metec/emulator.h"
#include "core/devices/metec/metec_device.h"
#include "core/devices/safety.h"
#include "core/devices/simulated_force.h"
#include "core/devices/simulated_tactile.h"
#include "core/devices/usb/libusb.h"

namespace enact::graph {
namespace {

// params that only some devices or transports read: given elsewhere, they are refused
void refuse_given(const Params& p, std::initializer_list<const char*> names, const std::string& only_for) {
  for (const char* n : names) {
    if (p.has(n)) throw config::Error(std::string("parameter ") + n + " is only for " + only_for + "\n  fix: remove it, or use " + only_for);
  }
}

// the hand of a simulated device, or of an emulated one: a scripted path or a virtual subject
void read_hand(const Params& p, devices::SimulatedForceParams& f) {
  f.hand_path = p.text("hand_path", "");
  f.subject = p.text("subject", "");
  f.subject_seed = static_cast<std::uint64_t>(p.integer("subject_seed", 0));
  f.noise_seed = static_cast<std::uint64_t>(p.integer("noise_seed", 0));
  f.start_m = p.vec3("start_m", f.start_m);
  f.hand_stiffness_n_per_m = p.number("hand_stiffness_n_per_m", f.hand_stiffness_n_per_m);
  f.hand_damping_n_s_per_m = p.number("hand_damping_n_s_per_m", f.hand_damping_n_s_per_m);
}

constexpr std::initializer_list<const char*> kHandParams = {"hand_path", "subject", "subject_seed", "noise_seed", "start_m",
                                                           "hand_stiffness_n_per_m", "hand_damping_n_s_per_m"};

// transport: usb (the machine's bus) or emulator (a fake bus with the device's emulator)
bool emulated(const Params& p) {
  const std::string t = p.text("transport", "usb");
  if (t != "usb" && t != "emulator") throw config::Error("transport '" + t + "' is not known\n  fix: use transport=usb (the real device) or transport=emulator");
  return t == "emulator";
}

std::unique_ptr<devices::ForceDevice> simulated_force(const Params& p) {
  refuse_given(p, {"transport", "serial", "firmware", "homing_timeout_s", "max_force_n"}, "device=falcon");
  devices::SimulatedForceParams f;
  f.profile = p.text("profile", f.profile);
  read_hand(p, f);
  return std::make_unique<devices::SimulatedForceDevice>(f);
}

std::unique_ptr<devices::ForceDevice> falcon_force(const Params& p) {
  refuse_given(p, {"profile"}, "device=simulated (the Falcon's profile is 'falcon')");
  devices::falcon::FalconParams f;
  f.serial = p.text("serial", "");
  f.firmware = p.text("firmware", "");
  f.homing_timeout_s = p.number("homing_timeout_s", f.homing_timeout_s);
  f.max_force_n = p.number("max_force_n", f.max_force_n);
  if (!emulated(p)) {
    refuse_given(p, kHandParams, "transport=emulator (the emulated hand)");
    return std::make_unique<devices::falcon::FalconForceDevice>(f, std::make_unique<devices::usb::LibusbBus>());
  }
  // the emulator: its firmware runs already unless the test of an upload is asked for
  devices::falcon::FalconEmulatorParams e;
  read_hand(p, e.grip);
  e.firmware_running = f.firmware.empty();
  auto bus = std::make_unique<devices::usb::FakeBus>();
  bus->add(devices::usb::emulated_device("falcon", std::make_shared<devices::falcon::FalconEmulator>(e)));
  return std::make_unique<devices::falcon::FalconForceDevice>(f, std::move(bus));
}

std::unique_ptr<devices::TactileDevice> metec_tactile(const Params& p, int rows, int cols, double rise_time_s) {
  devices::metec::MetecParams m;
  m.rows = rows;
  m.cols = cols;
  m.rise_time_s = rise_time_s;
  m.serial = p.text("serial", "");
  m.first_cell = p.integer("first_cell", m.first_cell);
  if (!emulated(p)) return std::make_unique<devices::metec::MetecTactileDevice>(m, std::make_unique<devices::usb::LibusbBus>());
  auto bus = std::make_unique<devices::usb::FakeBus>();
  bus->add(devices::usb::emulated_device("metec", std::make_shared<devices::metec::MetecEmulator>(devices::metec::MetecEmulatorParams{})));
  return std::make_unique<devices::metec::MetecTactileDevice>(m, std::move(bus));
}

}  // namespace

const std::vector<std::string> kSimParams{"scene", "rate_hz", "model", "tactile_period_s", "tactile_mode", "force",
                                          "min_fall_s", "min_recovery_s", "end_progress"};
const std::vector<std::string> kForceParams{"device", "profile", "hand_path", "subject", "subject_seed", "noise_seed", "start_m",
                                            "hand_stiffness_n_per_m", "hand_damping_n_s_per_m", "watchdog_s", "ramp_s", "reengage_s", "transport", "serial",
                                            "firmware", "homing_timeout_s", "max_force_n"};
const std::vector<std::string> kTactileParams{"device", "rows", "cols", "rise_time_s", "transport", "serial", "first_cell"};

sim::SimParams sim_params(const Params& p) {
  sim::SimParams s;
  s.scene = p.text("scene", "");
  if (s.scene.empty()) throw config::Error("the simulator needs a scene\n  fix: --param scene=launch/scenes/bridge.yaml");
  s.rate_hz = p.number("rate_hz", 0.0);
  s.model = p.text("model", s.model);
  s.tactile.period_s = p.number("tactile_period_s", s.tactile.period_s);
  s.tactile.mode = haptics::parse_tactile_mode(p.text("tactile_mode", "sample"));
  s.force = p.flag("force", false);
  s.task.min_fall_s = p.number("min_fall_s", s.task.min_fall_s);
  s.task.min_recovery_s = p.number("min_recovery_s", s.task.min_recovery_s);
  s.task.end_progress = p.number("end_progress", s.task.end_progress);
  return s;
}

std::unique_ptr<devices::ForceDevice> make_force_device(const Params& p) {
  const std::string device = p.text("device", "simulated");
  std::unique_ptr<devices::ForceDevice> inner;
  if (device == "simulated") {
    inner = simulated_force(p);
  } else if (device == "falcon") {
    inner = falcon_force(p);
  } else {
    throw config::Error("force device '" + device + "' is not known\n  fix: use device=simulated or device=falcon (a Novint Falcon over USB)");
  }
  devices::SafetyParams s;
  s.watchdog_s = p.number("watchdog_s", s.watchdog_s);
  s.ramp_s = p.number("ramp_s", s.ramp_s);
  s.reengage_s = p.number("reengage_s", s.reengage_s);
  auto device_ptr = std::make_unique<devices::SafeForceDevice>(std::move(inner), s);
  device_ptr->configure();
  return device_ptr;
}

std::unique_ptr<devices::TactileDevice> make_tactile_device(const Params& p) {
  const std::string device = p.text("device", "simulated");
  devices::SimulatedTactileParams t;
  t.rows = p.integer("rows", t.rows);
  t.cols = p.integer("cols", t.cols);
  t.rise_time_s = p.number("rise_time_s", t.rise_time_s);
  std::unique_ptr<devices::TactileDevice> out;
  if (device == "simulated") {
    refuse_given(p, {"transport", "serial", "first_cell"}, "device=metec");
    out = std::make_unique<devices::SimulatedTactileDevice>(t);
  } else if (device == "metec") {
    out = metec_tactile(p, t.rows, t.cols, t.rise_time_s);
  } else {
    throw config::Error("tactile device '" + device + "' is not known\n  fix: use device=simulated or device=metec (Metec Braille cells over USB)");
  }
  out->configure();
  return out;
}

}  // namespace enact::graph
