// A fake of Force Dimension's libdhd for tests (built as a shared library, loaded by the DHD
// backend with dlopen like the real one): the DHD functions enact binds, with the same C
// signatures, over a fake arm (fake_arm.h). Its frame, described by physical direction as
// the DHD documentation does: x points at the operator, y to the operator's right, z up;
// metres and newtons. fake_* functions let a test steer it (the test dlopens the same file,
// so both see one state).
#include <atomic>
#include <cstring>
#include <mutex>
#include <thread>
#include <string>

#include "tests/devices/vendor/fake_arm.h"

namespace {

using enact::math::Vec3;

// enact: x right, y away from the user, z up. Right is DHD +y; away from the user is DHD -x.
Vec3 enact_to_dhd(const Vec3& e) { return {-e.y, e.x, e.z}; }

struct Fake {
  std::mutex m;
  enact::test::fake::Arm arm{&enact_to_dhd};
  // set by the test's thread, read by the backend's: atomic
  std::atomic<bool> present{true};
  std::atomic<bool> calibrated{true};
  bool failing = false;
  bool open = false;
  bool force_enabled = false;
  std::atomic<unsigned int> buttons{0};
  std::string error = "no error";
  // the threads that called the device after dhdOpen: the DHD API wants one
  std::thread::id caller;
  std::atomic<int> callers{0};
};

Fake& fake() {
  static Fake f;
  return f;
}

// count a new calling thread (under f.m)
void note_caller(Fake& f) {
  if (f.callers.load() == 0 || f.caller != std::this_thread::get_id()) {
    f.caller = std::this_thread::get_id();
    f.callers.fetch_add(1);
  }
}

int fail(Fake& f, const char* why) {
  f.error = why;
  return -1;
}

}  // namespace

extern "C" {

int dhdGetDeviceCount() { return fake().present ? 1 : 0; }

int dhdOpen() {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (!f.present) return fail(f, "no device found");
  f.open = true;
  f.force_enabled = false;
  f.callers.store(0);
  f.arm.open();
  return 0;
}

int dhdClose(char) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  f.open = false;
  return 0;
}

// as SDK 3.x with DHD_MAX_STATUS 16: only 16 entries are written
int dhdGetStatus(int* status, char) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (!f.open) return fail(f, "device not open");
  std::memset(status, 0, 16 * sizeof(int));
  status[0] = 1;                  // power
  status[1] = 1;                  // connected
  status[3] = f.calibrated ? 0 : 1;  // RESET mode: not calibrated
  return 0;
}

int dhdEnableForce(unsigned char on, char) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (!f.open) return fail(f, "device not open");
  f.force_enabled = on != 0;
  return 0;
}

int dhdGetPosition(double* x, double* y, double* z, char) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (!f.open || f.failing) return fail(f, "communication error");
  note_caller(f);
  f.arm.advance();
  *x = f.arm.position_m().x;
  *y = f.arm.position_m().y;
  *z = f.arm.position_m().z;
  return 0;
}

int dhdGetLinearVelocity(double* x, double* y, double* z, char) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (!f.open || f.failing) return fail(f, "communication error");
  *x = f.arm.velocity_m_per_s().x;
  *y = f.arm.velocity_m_per_s().y;
  *z = f.arm.velocity_m_per_s().z;
  return 0;
}

int dhdSetForce(double x, double y, double z, char) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (!f.open || f.failing) return fail(f, "communication error");
  note_caller(f);
  f.arm.set_force(f.force_enabled ? Vec3{x, y, z} : Vec3{});
  return 0;
}

unsigned int dhdGetButtonMask(char) { return fake().buttons; }

const char* dhdErrorGetLastStr() { return fake().error.c_str(); }

// the test's levers
void fake_set_present(int present) { fake().present = present != 0; }
void fake_set_calibrated(int calibrated) { fake().calibrated = calibrated != 0; }
void fake_set_buttons(unsigned int mask) { fake().buttons = mask; }
void fake_set_failing(int failing) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  f.failing = failing != 0;
}
void fake_hold(double x, double y, double z) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  f.arm.hold({x, y, z});
}
void fake_force(double* out) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  out[0] = f.arm.force_n().x;
  out[1] = f.arm.force_n().y;
  out[2] = f.arm.force_n().z;
}
void fake_position(double* out) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  out[0] = f.arm.position_m().x;
  out[1] = f.arm.position_m().y;
  out[2] = f.arm.position_m().z;
}
int fake_is_open() { return fake().open ? 1 : 0; }
// how many times the calling thread of dhdGetPosition / dhdSetForce changed since dhdOpen (1: one thread)
int fake_callers() { return fake().callers.load(); }

}  // extern "C"
