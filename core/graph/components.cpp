#include "core/graph/components.h"

#include "core/config/yaml.h"
#include "core/devices/falcon/emulator.h"
#include "core/devices/falcon/falcon_device.h"
#include "core/devices/inverse3/emulated.h"
#include "core/devices/inverse3/inverse3_device.h"
#include "core/devices/metec/emulator.h"
#include "core/devices/metec/metec_device.h"
#include "core/devices/safety.h"
#include "core/devices/simulated_force.h"
#include "core/devices/simulated_tactile.h"
#include "core/devices/usb/libusb.h"
#include "core/devices/vendor/dhd_device.h"
#include "core/devices/vendor/hd_device.h"
#include "core/graph/node_params.h"
#include "core/graph/param_binding.h"
#include "core/physics/scene.h"

namespace enact::graph {
namespace {

// params that only some devices or transports read: given elsewhere, they are refused
void refuse_given(const Params& p, std::initializer_list<const char*> names, const std::string& only_for) {
  for (const char* n : names) {
    if (p.has(n)) throw config::Error(std::string("parameter ") + n + " is only for " + only_for + "\n  fix: remove it, or use " + only_for);
  }
}

// where the end-effector starts: start_m when given, else where the scene's body is, else
// `otherwise` (the device's own default)
math::Vec3 start_position(const Params& p, const math::Vec3& otherwise) {
  if (!p.text("start_m").empty()) return p.vec3("start_m");
  if (p.text("start_scene").empty()) return otherwise;
  const physics::Model scene = physics::load_scene(p.text("start_scene"));
  if (scene.proxies.empty()) throw config::Error(p.text("start_scene") + ": the scene has no body, so no start position\n  fix: add a body: section, or give start_m");
  return scene.points[scene.proxies[0].point].position_m;
}

// the hand of a simulated device, or of an emulated one: a scripted path or a virtual subject
void read_hand(const Params& p, devices::SimulatedForceParams& f) {
  f.hand_path = p.text("hand_path");
  f.subject = p.text("subject");
  f.subject_seed = static_cast<std::uint64_t>(p.integer("subject_seed"));
  f.noise_seed = static_cast<std::uint64_t>(p.integer("noise_seed"));
  f.start_m = start_position(p, f.start_m);
  f.hand_stiffness_n_per_m = p.number("hand_stiffness_n_per_m");
  f.hand_damping_n_s_per_m = p.number("hand_damping_n_s_per_m");
}

constexpr std::initializer_list<const char*> kHandParams = {"hand_path", "subject", "subject_seed", "noise_seed", "start_m", "start_scene",
                                                           "hand_stiffness_n_per_m", "hand_damping_n_s_per_m"};

// transport: usb (the machine's bus) or emulator (a fake bus with the device's emulator)
bool emulated(const Params& p) { return p.text("transport") == "emulator"; }

constexpr std::initializer_list<const char*> kFalconParams = {"serial", "firmware", "homing_timeout_s", "max_force_n"};
constexpr const char* kTransportDevices = "device=falcon or device=inverse3";

constexpr std::initializer_list<const char*> kInverse3Params = {"port", "events_port", "device_id", "origin_m"};

std::unique_ptr<devices::ForceDevice> simulated_force(const Params& p) {
  refuse_given(p, {"transport"}, kTransportDevices);
  refuse_given(p, kFalconParams, "device=falcon");
  refuse_given(p, {"library", "device_name"}, "device=dhd or device=hd");
  refuse_given(p, kInverse3Params, "device=inverse3");
  devices::SimulatedForceParams f;
  f.profile = p.text("profile");
  read_hand(p, f);
  return std::make_unique<devices::SimulatedForceDevice>(f);
}

std::unique_ptr<devices::ForceDevice> falcon_force(const Params& p) {
  refuse_given(p, {"profile"}, "device=simulated (the Falcon's profile is 'falcon')");
  refuse_given(p, {"library", "device_name"}, "device=dhd or device=hd");
  refuse_given(p, kInverse3Params, "device=inverse3");
  devices::falcon::FalconParams f;
  f.serial = p.text("serial");
  f.firmware = p.text("firmware");
  f.homing_timeout_s = p.number("homing_timeout_s");
  f.max_force_n = p.number("max_force_n");
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

// a vendor SDK's device: a person holds it (no scripted hand here: a fake library's own hand
// stands in for one in tests), the Falcon's params do not apply
void refuse_for_vendor(const Params& p) {
  refuse_given(p, {"transport"}, kTransportDevices);
  refuse_given(p, kFalconParams, "device=falcon");
  refuse_given(p, kInverse3Params, "device=inverse3");
  refuse_given(p, kHandParams, "device=simulated or device=falcon with transport=emulator (a real device is held by a person)");
}

std::unique_ptr<devices::ForceDevice> dhd_force(const Params& p) {
  refuse_for_vendor(p);
  refuse_given(p, {"device_name"}, "device=hd");
  devices::vendor::DhdParams d;
  if (p.has("library")) d.library = p.text("library");
  if (p.has("profile")) d.profile = p.text("profile");
  return std::make_unique<devices::vendor::DhdForceDevice>(d);
}

std::unique_ptr<devices::ForceDevice> hd_force(const Params& p) {
  refuse_for_vendor(p);
  devices::vendor::HdParams h;
  if (p.has("library")) h.library = p.text("library");
  if (p.has("profile")) h.profile = p.text("profile");
  h.device_name = p.text("device_name");
  return std::make_unique<devices::vendor::HdForceDevice>(h);
}

// the Haply Inverse3: through the Inverse Service, or (transport=emulator) an emulated service
// in this process whose handle the emulator's hand holds
std::unique_ptr<devices::ForceDevice> inverse3_force(const Params& p) {
  refuse_given(p, kFalconParams, "device=falcon");
  refuse_given(p, {"library", "device_name"}, "device=dhd or device=hd");
  devices::inverse3::Inverse3Params d;
  d.port = static_cast<int>(p.integer("port"));
  d.events_port = static_cast<int>(p.integer("events_port"));
  d.device_id = p.text("device_id");
  d.origin_m = p.vec3("origin_m");
  if (p.has("profile")) d.profile = p.text("profile");
  if (!emulated(p)) {
    refuse_given(p, kHandParams, "transport=emulator (the emulated hand)");
    return std::make_unique<devices::inverse3::Inverse3ForceDevice>(d);
  }
  refuse_given(p, {"port", "events_port", "device_id"}, "transport=usb (the emulator takes free ports)");
  devices::inverse3::Inverse3EmulatorParams e;
  read_hand(p, e.handle);
  e.handle.profile = d.profile;
  e.origin_m = d.origin_m;
  return std::make_unique<devices::inverse3::EmulatedInverse3>(d, e);
}

// the force device named by `device` (a device the table does not name is refused by declare())
std::unique_ptr<devices::ForceDevice> inner_force_device(const Params& p, const std::string& device) {
  if (device == "falcon") return falcon_force(p);
  if (device == "dhd") return dhd_force(p);
  if (device == "hd") return hd_force(p);
  if (device == "inverse3") return inverse3_force(p);
  return simulated_force(p);
}

std::unique_ptr<devices::TactileDevice> metec_tactile(const TactileConfig& c) {
  devices::metec::MetecParams m = c.metec;
  m.rows = c.cells.rows;
  m.cols = c.cells.cols;
  m.rise_time_s = c.cells.rise_time_s;
  if (c.transport != "emulator") return std::make_unique<devices::metec::MetecTactileDevice>(m, std::make_unique<devices::usb::LibusbBus>());
  auto bus = std::make_unique<devices::usb::FakeBus>();
  bus->add(devices::usb::emulated_device("metec", std::make_shared<devices::metec::MetecEmulator>(devices::metec::MetecEmulatorParams{})));
  return std::make_unique<devices::metec::MetecTactileDevice>(m, std::move(bus));
}

}  // namespace

sim::SimParams sim_params(const Params& p) { return sim_bindings().read(p); }

std::unique_ptr<devices::ForceDevice> make_force_device(const Params& p) {
  p.declare(force_table());
  std::unique_ptr<devices::ForceDevice> inner = inner_force_device(p, p.text("device"));
  devices::SafetyParams s;
  s.watchdog_s = p.number("watchdog_s");
  s.ramp_s = p.number("ramp_s");
  s.reengage_s = p.number("reengage_s");
  auto device_ptr = std::make_unique<devices::SafeForceDevice>(std::move(inner), s);
  device_ptr->configure();
  return device_ptr;
}

std::unique_ptr<devices::TactileDevice> make_tactile_device(const Params& p) {
  const TactileConfig c = tactile_bindings().read(p);
  std::unique_ptr<devices::TactileDevice> out;
  if (c.device == "metec") {
    out = metec_tactile(c);
  } else {
    refuse_given(p, {"transport", "serial", "first_cell"}, "device=metec");
    out = std::make_unique<devices::SimulatedTactileDevice>(c.cells);
  }
  out->configure();
  return out;
}

}  // namespace enact::graph
