#include "core/node/components.h"

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
#include "core/params/device_config.h"
#include "core/params/node_params.h"
#include "core/params/param_binding.h"
#include "core/physics/scene.h"
#include "core/sim/offline.h"

#include <cstdio>

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
void read_hand(const Params& p, const ForceConfig& c, devices::SimulatedForceParams& f) {
  f.hand_path = c.hand.hand_path;
  f.subject = c.hand.subject;
  f.subject_seed = c.hand.subject_seed;
  f.noise_seed = c.hand.noise_seed;
  f.start_m = start_position(p, f.start_m);
  // a scripted hand that never reaches the graph's scene feels nothing: said before it starts
  if (!f.hand_path.empty() && !p.text("start_scene").empty()) {
    if (const std::string warning = sim::hand_path_warning(p.text("start_scene"), f.hand_path); !warning.empty()) std::fprintf(stderr, "warning: %s\n", warning.c_str());
  }
  f.hand_stiffness_n_per_m = c.hand.hand_stiffness_n_per_m;
  f.hand_damping_n_s_per_m = c.hand.hand_damping_n_s_per_m;
}

constexpr std::initializer_list<const char*> kHandParams = {"hand_path", "subject", "subject_seed", "noise_seed", "start_m", "start_scene",
                                                           "hand_stiffness_n_per_m", "hand_damping_n_s_per_m"};

// transport: usb (the machine's bus) or emulator (a fake bus with the device's emulator)
bool emulated(const ForceConfig& c) { return c.transport == "emulator"; }

constexpr std::initializer_list<const char*> kFalconParams = {"serial", "firmware", "homing_timeout_s", "max_force_n"};
constexpr const char* kTransportDevices = "device=falcon or device=inverse3";

constexpr std::initializer_list<const char*> kInverse3Params = {"port", "events_port", "device_id", "origin_m"};

std::unique_ptr<devices::ForceDevice> simulated_force(const Params& p, const ForceConfig& c) {
  refuse_given(p, {"transport"}, kTransportDevices);
  refuse_given(p, kFalconParams, "device=falcon");
  refuse_given(p, {"library", "device_name"}, "device=dhd or device=hd");
  refuse_given(p, kInverse3Params, "device=inverse3");
  devices::SimulatedForceParams f;
  f.profile = c.hand.profile;
  read_hand(p, c, f);
  return std::make_unique<devices::SimulatedForceDevice>(f);
}

std::unique_ptr<devices::ForceDevice> falcon_force(const Params& p, const ForceConfig& c) {
  refuse_given(p, {"profile"}, "device=simulated (the Falcon's profile is 'falcon')");
  refuse_given(p, {"library", "device_name"}, "device=dhd or device=hd");
  refuse_given(p, kInverse3Params, "device=inverse3");
  const devices::falcon::FalconParams& f = c.falcon;
  if (!emulated(c)) {
    refuse_given(p, kHandParams, "transport=emulator (the emulated hand)");
    return std::make_unique<devices::falcon::FalconForceDevice>(f, std::make_unique<devices::usb::LibusbBus>());
  }
  // the emulator: its firmware runs already unless the test of an upload is asked for
  devices::falcon::FalconEmulatorParams e;
  read_hand(p, c, e.grip);
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

std::unique_ptr<devices::ForceDevice> dhd_force(const Params& p, const ForceConfig& c) {
  refuse_for_vendor(p);
  refuse_given(p, {"device_name"}, "device=hd");
  devices::vendor::DhdParams d;
  if (p.has("library")) d.library = c.library;
  if (p.has("profile")) d.profile = c.hand.profile;
  return std::make_unique<devices::vendor::DhdForceDevice>(d);
}

std::unique_ptr<devices::ForceDevice> hd_force(const Params& p, const ForceConfig& c) {
  refuse_for_vendor(p);
  devices::vendor::HdParams h;
  if (p.has("library")) h.library = c.library;
  if (p.has("profile")) h.profile = c.hand.profile;
  h.device_name = c.device_name;
  return std::make_unique<devices::vendor::HdForceDevice>(h);
}

// the Haply Inverse3: through the Inverse Service, or (transport=emulator) an emulated service
// in this process whose handle the emulator's hand holds
std::unique_ptr<devices::ForceDevice> inverse3_force(const Params& p, const ForceConfig& c) {
  refuse_given(p, kFalconParams, "device=falcon");
  refuse_given(p, {"library", "device_name"}, "device=dhd or device=hd");
  devices::inverse3::Inverse3Params d = c.inverse3;
  if (p.has("profile")) d.profile = c.hand.profile;
  if (!emulated(c)) {
    refuse_given(p, kHandParams, "transport=emulator (the emulated hand)");
    return std::make_unique<devices::inverse3::Inverse3ForceDevice>(d);
  }
  refuse_given(p, {"port", "events_port", "device_id"}, "transport=usb (the emulator takes free ports)");
  devices::inverse3::Inverse3EmulatorParams e;
  read_hand(p, c, e.handle);
  e.handle.profile = d.profile;
  e.origin_m = d.origin_m;
  return std::make_unique<devices::inverse3::EmulatedInverse3>(d, e);
}

// the force device named by `device` (a device the table does not name is refused by declare())
std::unique_ptr<devices::ForceDevice> inner_force_device(const Params& p, const ForceConfig& c) {
  if (c.device == "falcon") return falcon_force(p, c);
  if (c.device == "dhd") return dhd_force(p, c);
  if (c.device == "hd") return hd_force(p, c);
  if (c.device == "inverse3") return inverse3_force(p, c);
  return simulated_force(p, c);
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

std::unique_ptr<devices::ForceDevice> make_force_device(const Params& p) {
  const ForceConfig c = force_bindings().read(p);
  auto device_ptr = std::make_unique<devices::SafeForceDevice>(inner_force_device(p, c), c.safety);
  device_ptr->configure();
  return device_ptr;
}

std::string safety_summary(const devices::ForceDevice& device) {
  const auto* safe = dynamic_cast<const devices::SafeForceDevice*>(&device);
  if (!safe) return "no safety layer";
  const bool zero = safe->sent_force_n() == math::Vec3{};
  return "force steps held to the profile's limit: " + std::to_string(safe->slew_limited()) + ", re-engagements: " +
         std::to_string(safe->reengagements()) + "; force at exit: " + (zero ? "zeroed before the device was switched off" : "NOT zero");
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
