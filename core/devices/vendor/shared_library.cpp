#include "core/devices/vendor/shared_library.h"

#include <dlfcn.h>

#include <utility>

#include "core/config/share.h"
#include "core/devices/params_error.h"

namespace enact::devices::vendor {

SharedLibrary::SharedLibrary(const std::string& path, const char* device, const std::string& fix) : path_(path), device_(device) {
  handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle_ == nullptr) {
    const char* why = dlerror();
    refuse(device, "cannot load " + path + " (" + (why ? why : "unknown error") + ")", fix);
  }
}

SharedLibrary::~SharedLibrary() {
  if (handle_ != nullptr) dlclose(handle_);
}

SharedLibrary::SharedLibrary(SharedLibrary&& other) noexcept
    : handle_(std::exchange(other.handle_, nullptr)), path_(std::move(other.path_)), device_(other.device_) {}

SharedLibrary& SharedLibrary::operator=(SharedLibrary&& other) noexcept {
  if (this != &other) {
    if (handle_ != nullptr) dlclose(handle_);
    handle_ = std::exchange(other.handle_, nullptr);
    path_ = std::move(other.path_);
    device_ = other.device_;
  }
  return *this;
}

void* SharedLibrary::address(const char* name) const {
  dlerror();
  void* p = handle_ ? dlsym(handle_, name) : nullptr;
  if (p == nullptr) {
    refuse(device_, path_ + " has no function " + name + " (not the vendor's library, or an SDK too old)",
           "install the vendor's SDK (see " + config::shipped("docs/devices.md") + ") and name its library file");
  }
  return p;
}

bool loadable(const std::string& path, std::string& why) {
  void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (h == nullptr) {
    const char* e = dlerror();
    why = e ? e : "unknown error";
    return false;
  }
  dlclose(h);
  return true;
}

}  // namespace enact::devices::vendor
