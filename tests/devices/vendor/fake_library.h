#pragma once
// A test's hold on a fake vendor library (fake_dhd.cpp, fake_hd.cpp): the same file the
// backend loads, opened again (dlopen gives the same copy, so one state), with its fake_*
// levers bound. set_up() puts every lever back to a present, calibrated, quiet device held
// at the device origin.
#include <dlfcn.h>

#include <stdexcept>
#include <string>

#include "core/math/vec3.h"

namespace enact::test {

class FakeLibrary {
 public:
  explicit FakeLibrary(const std::string& path) : handle_(dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) {
    if (handle_ == nullptr) throw std::runtime_error("cannot load the fake library " + path);
    bind("fake_set_present", set_present);
    bind("fake_set_calibrated", set_calibrated);
    bind("fake_set_buttons", set_buttons);
    bind("fake_set_failing", set_failing);
    bind("fake_hold", hold_raw);
    bind("fake_force", force_raw);
    bind("fake_position", position_raw);
    bind("fake_is_open", is_open);
  }
  ~FakeLibrary() { dlclose(handle_); }
  FakeLibrary(const FakeLibrary&) = delete;
  FakeLibrary& operator=(const FakeLibrary&) = delete;

  void set_up() const {
    set_present(1);
    set_calibrated(1);
    set_buttons(0);
    set_failing(0);
    hold({});
  }
  // the hand holds the handle at p (the device's frame, metres)
  void hold(const math::Vec3& p) const { hold_raw(p.x, p.y, p.z); }
  // the force acting on the handle now (the device's frame, N)
  math::Vec3 force_n() const {
    double f[3];
    force_raw(f);
    return {f[0], f[1], f[2]};
  }
  // where the handle is (the device's frame, metres)
  math::Vec3 position_m() const {
    double p[3];
    position_raw(p);
    return {p[0], p[1], p[2]};
  }

  void (*set_present)(int) = nullptr;
  void (*set_calibrated)(int) = nullptr;
  void (*set_buttons)(unsigned int) = nullptr;
  void (*set_failing)(int) = nullptr;
  int (*is_open)() = nullptr;

 private:
  template <class F>
  void bind(const char* name, F& out) {
    out = reinterpret_cast<F>(dlsym(handle_, name));
    if (out == nullptr) throw std::runtime_error(std::string("the fake library has no ") + name);
  }
  void* handle_;
  void (*hold_raw)(double, double, double) = nullptr;
  void (*force_raw)(double*) = nullptr;
  void (*position_raw)(double*) = nullptr;
};

}  // namespace enact::test
