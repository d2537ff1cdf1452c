#include "core/devices/vendor/probe.h"

#include "core/config/yaml.h"
#include "core/devices/vendor/dhd_device.h"
#include "core/devices/vendor/hd_device.h"

namespace enact::devices::vendor {
namespace {

// "NAME (device: BACKEND): ..." lines
std::string line(const char* what, const std::string& text) { return std::string(what) + ": " + text + "\n"; }

// the library and its functions, or why not (the loader's error, with the fix)
template <class Api>
bool load(const std::string& library, const char* device, SharedLibrary& out, Api& api, std::string& why) {
  try {
    out = SharedLibrary(library, device, "");
    api.bind(out);
    return true;
  } catch (const config::Error& e) {
    why = e.what();
    if (const auto cut = why.find("\n  fix:"); cut != std::string::npos) why.erase(cut);
    if (const std::string prefix = std::string(device) + ": "; why.rfind(prefix, 0) == 0) why.erase(0, prefix.size());
    return false;
  }
}

}  // namespace

Presence probe_dhd(const std::string& library) {
  constexpr const char* kWhat = "Force Dimension (device: dhd)";
  SharedLibrary lib;
  DhdApi api;
  std::string why;
  if (!load(library, "dhd", lib, api, why)) {
    return {false, line(kWhat, "absent: " + why) + "  fix: install the Force Dimension SDK and pass its libdhd.so with --dhd-library PATH (or put its folder on LD_LIBRARY_PATH)\n"};
  }
  const int count = api.device_count();
  if (count <= 0) {
    return {false, line(kWhat, library + " loads; no device found") + "  fix: plug the device in and power it on; without root, install the udev rules (enact devices --udev-rules)\n"};
  }
  return {true, line(kWhat, std::to_string(count) + " device(s) found through " + library + "  ready (launch/bridge_rt_dhd.yaml)")};
}

Presence probe_hd(const std::string& library, const std::string& device_name) {
  constexpr const char* kWhat = "OpenHaptics (device: hd)";
  SharedLibrary lib;
  HdApi api;
  std::string why;
  if (!load(library, "hd", lib, api, why)) {
    return {false, line(kWhat, "absent: " + why) + "  fix: install OpenHaptics for Linux and the Touch driver, and pass libHD.so with --hd-library PATH\n"};
  }
  const HHD device = api.init_device(device_name.empty() ? nullptr : device_name.c_str());
  if (const std::string error = api.last_error(); !error.empty() || device == kHdInvalidHandle) {
    const std::string name = device_name.empty() ? "the default device" : "'" + device_name + "'";
    return {false, line(kWhat, library + " loads; " + name + " does not open: " + error) +
                       "  fix: plug the Touch in and set it up in Touch Setup (name it with --hd-device NAME); check that you may open its device file\n"};
  }
  api.disable_device(device);
  return {true, line(kWhat, (device_name.empty() ? std::string("the default device") : "'" + device_name + "'") + " opens through " + library + "  ready (launch/bridge_rt_hd.yaml)")};
}

}  // namespace enact::devices::vendor
