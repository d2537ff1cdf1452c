#pragma once
// The arm inside the fake vendor libraries (fake_dhd.cpp, fake_hd.cpp), which stand in for
// Force Dimension's libdhd and OpenHaptics' libHD in tests: a handle of 0.1 kg, pushed by the
// force the program commands and held by a hand, a spring-damper (200 N/m, 4 N s/m) pulling
// it towards the hand's target. So a force the program sends the wrong way, in the wrong
// unit or on the wrong axis moves the handle where the test does not expect it.
//
// The hand's target, in the device's own frame: held where fake_hold puts it, or, when the
// environment variable ENACT_FAKE_HAND_PATH names a CSV (t_s,x_m,y_m,z_m in the enact frame,
// a header line first), that path from the device's opening on, turned into the device frame
// by the fake's own description of its axes (enact_to_device). The handle starts on the
// target, at rest. Time is the real monotonic clock.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "core/math/vec3.h"

namespace enact::test::fake {

using math::Vec3;

class Arm {
 public:
  static constexpr double kMass_kg = 0.1;
  static constexpr double kHandStiffness_n_per_m = 200.0;
  static constexpr double kHandDamping_n_s_per_m = 4.0;
  static constexpr double kSubstep_s = 1e-4;

  explicit Arm(Vec3 (*enact_to_device)(const Vec3&)) : enact_to_device_(enact_to_device) {}

  // the device was opened: the path (if any) from now on, the handle on the target at rest
  void open() {
    path_.clear();
    if (const char* file = std::getenv("ENACT_FAKE_HAND_PATH"); file != nullptr && *file != '\0') load(file);
    start_ = last_ = std::chrono::steady_clock::now();
    position_m_ = target(0.0);
    velocity_m_per_s_ = {};
    force_n_ = {};
  }
  // the hand holds its target at p (device frame, m); the path, if any, is dropped
  void hold(const Vec3& p) {
    path_.clear();
    held_m_ = p;
  }
  // integrate up to now
  void advance() {
    const auto now = std::chrono::steady_clock::now();
    double dt_s = std::min(std::chrono::duration<double>(now - last_).count(), 0.05);
    last_ = now;
    double t_s = std::chrono::duration<double>(now - start_).count() - dt_s;
    while (dt_s > 0.0) {
      const double h = std::min(dt_s, kSubstep_s);
      t_s += h;
      const Vec3 hand = (target(t_s) - position_m_) * kHandStiffness_n_per_m - velocity_m_per_s_ * kHandDamping_n_s_per_m;
      velocity_m_per_s_ += (force_n_ + hand) * (h / kMass_kg);
      position_m_ += velocity_m_per_s_ * h;
      dt_s -= h;
    }
  }
  void set_force(const Vec3& f) { force_n_ = f; }
  const Vec3& force_n() const { return force_n_; }
  const Vec3& position_m() const { return position_m_; }
  const Vec3& velocity_m_per_s() const { return velocity_m_per_s_; }

 private:
  void load(const char* file) {
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      std::array<double, 4> row{};
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream fields(line);
      if (fields >> row[0] >> row[1] >> row[2] >> row[3]) path_.push_back(row);
    }
    if (path_.empty()) std::fprintf(stderr, "fake arm: no path points in %s\n", file);
  }
  Vec3 target(double t_s) const {
    if (path_.empty()) return held_m_;
    auto after = std::find_if(path_.begin(), path_.end(), [&](const auto& r) { return r[0] > t_s; });
    if (after == path_.begin()) return enact_to_device_({path_.front()[1], path_.front()[2], path_.front()[3]});
    if (after == path_.end()) return enact_to_device_({path_.back()[1], path_.back()[2], path_.back()[3]});
    const auto& a = *(after - 1);
    const auto& b = *after;
    const double u = (t_s - a[0]) / (b[0] - a[0]);
    return enact_to_device_({a[1] + (b[1] - a[1]) * u, a[2] + (b[2] - a[2]) * u, a[3] + (b[3] - a[3]) * u});
  }

  Vec3 (*enact_to_device_)(const Vec3&);
  std::vector<std::array<double, 4>> path_;
  Vec3 held_m_;
  Vec3 position_m_, velocity_m_per_s_, force_n_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace enact::test::fake
