// A fake of OpenHaptics' libHD for tests (built as a shared library, loaded by the HD backend
// with dlopen like the real one): the HD functions enact binds, with the same C signatures
// and enum values, over a fake arm (fake_arm.h), and a scheduler thread that calls the
// scheduled callbacks every millisecond, as HD's servo loop does. Its frame, described by
// physical direction as the OpenHaptics guide does: x to the right, y up, z towards the
// user; positions in millimetres, velocities in mm/s, forces in newtons. hdGetError pops the
// oldest error. fake_* functions let a test steer it.
#include <atomic>
#include <chrono>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/devices/vendor/hd_device.h"
#include "tests/devices/vendor/fake_arm.h"

namespace {

using enact::math::Vec3;

// enact: x right, y away from the user, z up. Right is HD +x; up is HD +y; away is HD -z.
Vec3 enact_to_hd(const Vec3& e) { return {e.x, e.z, -e.y}; }

constexpr double kMillimetresPerMetre = 1000.0;

// the SDK's error record as the backend declares it (hd_device.h stands for hdDefines.h on both
// sides, as the SDK's header does for a program and the library: a type of the fake's own
// would make the backend call hdGetError through a pointer of another function type)
using enact::devices::vendor::HDErrorInfo;
using Callback = unsigned int (*)(void*);
struct Scheduled {
  unsigned long handle;
  Callback callback;
  void* data;
};

struct Fake {
  std::recursive_mutex m;
  enact::test::fake::Arm arm{&enact_to_hd};
  // set by the test's thread, read by the backend's: atomic
  std::atomic<bool> present{true};
  std::atomic<bool> calibrated{true};
  bool failing = false;
  bool open = false;
  bool force_output = false;
  std::atomic<int> buttons{0};
  Vec3 pending_force_n;
  std::deque<unsigned int> errors;
  std::vector<Scheduled> scheduled;
  unsigned long next_handle = 1;
  std::thread scheduler;
  std::atomic<bool> running{false};
  std::atomic<int> frame_calls_off_servo{0};  // frame and state calls from a thread not the servo loop's
};

Fake& fake() {
  static Fake f;
  return f;
}

constexpr unsigned int kInvalidEnum = 0x0100;
constexpr unsigned int kCommError = 0x0201;
constexpr unsigned int kInvalidHandle = 0xFFFFFFFFu;

thread_local bool on_servo_thread = false;

// the HD API reads and writes device state in a frame, in the servo loop
void check_servo_thread() {
  if (!on_servo_thread) fake().frame_calls_off_servo.fetch_add(1);
}

void servo_loop() {
  on_servo_thread = true;
  Fake& f = fake();
  auto next = std::chrono::steady_clock::now();
  while (f.running.load()) {
    std::vector<Scheduled> now;
    {
      std::lock_guard lock(f.m);
      now = f.scheduled;
    }
    for (const Scheduled& s : now) {
      if (s.callback(s.data) == 0) {  // HD_CALLBACK_DONE
        std::lock_guard lock(f.m);
        std::erase_if(f.scheduled, [&](const Scheduled& x) { return x.handle == s.handle; });
      }
    }
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);
  }
}

}  // namespace

extern "C" {

unsigned int hdInitDevice(const char* name) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (!f.present || (name != nullptr && std::string(name) != "Default Device")) {
    f.errors.push_back(kCommError);
    return kInvalidHandle;
  }
  f.open = true;
  f.force_output = false;
  f.pending_force_n = {};
  f.arm.open();
  return 1;
}

void hdDisableDevice(unsigned int) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  f.open = false;
  f.force_output = false;
}

HDErrorInfo hdGetError() {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (f.errors.empty()) return {0, 0, 1};
  const unsigned int code = f.errors.front();
  f.errors.pop_front();
  return {code, 0, 1};
}

const char* hdGetErrorString(unsigned int code) { return code == kCommError ? "communication error (fake)" : "fake HD error"; }

void hdBeginFrame(unsigned int) {
  check_servo_thread();
  Fake& f = fake();
  std::lock_guard lock(f.m);
  f.arm.advance();
}

void hdEndFrame(unsigned int) {
  check_servo_thread();
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (f.failing) f.errors.push_back(kCommError);
  f.arm.set_force(f.force_output && !f.failing ? f.pending_force_n : Vec3{});
}

void hdGetDoublev(unsigned int name, double* out) {
  check_servo_thread();
  Fake& f = fake();
  std::lock_guard lock(f.m);
  Vec3 v;
  if (name == 0x2050) {
    v = f.arm.position_m() * kMillimetresPerMetre;
  } else if (name == 0x2051) {
    v = f.arm.velocity_m_per_s() * kMillimetresPerMetre;
  } else {
    f.errors.push_back(kInvalidEnum);
    return;
  }
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
}

void hdGetIntegerv(unsigned int name, int* out) {
  check_servo_thread();
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (name != 0x2000) {
    f.errors.push_back(kInvalidEnum);
    return;
  }
  *out = f.buttons;
}

void hdSetDoublev(unsigned int name, const double* in) {
  check_servo_thread();
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (name != 0x2700) {
    f.errors.push_back(kInvalidEnum);
    return;
  }
  f.pending_force_n = {in[0], in[1], in[2]};
}

void hdEnable(unsigned int cap) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  if (cap == 0x4000) {
    f.force_output = true;
  } else {
    f.errors.push_back(kInvalidEnum);
  }
}

unsigned int hdCheckCalibration() { return fake().calibrated ? 0x5000 : 0x5001; }

unsigned long hdScheduleAsynchronous(Callback callback, void* data, unsigned short) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  f.scheduled.push_back({f.next_handle, callback, data});
  return f.next_handle++;
}

void hdUnschedule(unsigned long handle) {
  Fake& f = fake();
  std::lock_guard lock(f.m);
  std::erase_if(f.scheduled, [&](const Scheduled& s) { return s.handle == handle; });
}

void hdStartScheduler() {
  Fake& f = fake();
  if (f.running.exchange(true)) return;
  f.scheduler = std::thread(servo_loop);
}

void hdStopScheduler() {
  Fake& f = fake();
  f.running.store(false);
  if (f.scheduler.joinable()) f.scheduler.join();
}

// the test's levers
void fake_set_present(int present) { fake().present = present != 0; }
void fake_set_calibrated(int calibrated) { fake().calibrated = calibrated != 0; }
void fake_set_buttons(unsigned int mask) { fake().buttons = static_cast<int>(mask); }
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
int fake_scheduler_running() { return fake().running.load() ? 1 : 0; }
int fake_frame_calls_off_servo() { return fake().frame_calls_off_servo.load(); }

}  // extern "C"
