#include "core/devices/device_profile.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace enact::devices {
namespace {

TEST(DeviceProfile, ErgosHasThePublishedFigures) {
  const auto p = find_device_profile("ergos");
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->name, "ergos");
  EXPECT_NEAR(p->workspace_max_m.x - p->workspace_min_m.x, 0.060, 1e-12);
  EXPECT_NEAR(p->workspace_max_m.y - p->workspace_min_m.y, 0.060, 1e-12);
  EXPECT_NEAR(p->workspace_max_m.z - p->workspace_min_m.z, 0.025, 1e-12);
  EXPECT_DOUBLE_EQ(p->peak_force_n, 200.0);
  EXPECT_DOUBLE_EQ(p->continuous_force_n, 60.0);
  EXPECT_DOUBLE_EQ(p->max_speed_m_per_s, 1.8);
  EXPECT_DOUBLE_EQ(p->resolution_m, 1e-6);
  EXPECT_GT(p->damping_n_s_per_m, 0.0);
}

TEST(DeviceProfile, UnknownNameIsAbsent) {
  EXPECT_FALSE(find_device_profile("phantom").has_value());
  EXPECT_FALSE(find_device_profile("").has_value());
}

TEST(DeviceProfile, NamesListEveryProfile) {
  const auto names = device_profile_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "ergos"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "falcon"), names.end());
  for (const auto& n : names) EXPECT_TRUE(find_device_profile(n).has_value()) << n;
}

TEST(DeviceProfile, EveryProfileIsConsistent) {
  for (const auto& n : device_profile_names()) {
    const auto p = *find_device_profile(n);
    EXPECT_LT(p.workspace_min_m.x, p.workspace_max_m.x) << n;
    EXPECT_LT(p.workspace_min_m.y, p.workspace_max_m.y) << n;
    EXPECT_LT(p.workspace_min_m.z, p.workspace_max_m.z) << n;
    EXPECT_GT(p.peak_force_n, 0.0) << n;
    EXPECT_LE(p.continuous_force_n, p.peak_force_n) << n;
    EXPECT_GT(p.max_force_step_n_per_ms, 0.0) << n;
    EXPECT_LT(p.max_force_step_n_per_ms, p.peak_force_n) << n << ": a step limit at or over the peak limits nothing";
    EXPECT_GE(p.max_stiffness_n_per_m, 0.0) << n;
  }
}

TEST(DeviceProfile, TheVendorDevicesHaveTheirProfiles) {
  // the Touch's data sheet figures as transcribed (to check against the current sheet)
  const auto touch = find_device_profile("touch");
  ASSERT_TRUE(touch.has_value());
  EXPECT_NEAR(touch->workspace_max_m.x - touch->workspace_min_m.x, 0.160, 1e-12);
  EXPECT_NEAR(touch->workspace_max_m.y - touch->workspace_min_m.y, 0.070, 1e-12);
  EXPECT_NEAR(touch->workspace_max_m.z - touch->workspace_min_m.z, 0.120, 1e-12);
  EXPECT_DOUBLE_EQ(touch->peak_force_n, 3.3);
  EXPECT_DOUBLE_EQ(touch->continuous_force_n, 0.88);
  const auto omega = find_device_profile("omega3");
  ASSERT_TRUE(omega.has_value());
  EXPECT_DOUBLE_EQ(omega->continuous_force_n, 12.0);
  EXPECT_DOUBLE_EQ(omega->max_stiffness_n_per_m, 14500.0);
  EXPECT_TRUE(find_device_profile("inverse3").has_value());
}

}  // namespace
}  // namespace enact::devices
