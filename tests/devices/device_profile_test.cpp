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

}  // namespace
}  // namespace enact::devices
