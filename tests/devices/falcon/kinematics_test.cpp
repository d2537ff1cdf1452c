// The Falcon's kinematics: forward(inverse(p)) = p within 1 um over the workspace, the
// analytic Jacobian against finite differences, forces through the transposed Jacobian
// checked by virtual work, the encoder scale, the frames.
#include "core/devices/falcon/kinematics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace enact::devices::falcon {
namespace {

constexpr double kHalf_m = 0.04;  // the workspace checked: a 80 mm cube about the centre

double distance(const Vec3& a, const Vec3& b) { return math::norm(a - b); }

std::array<double, 3> arm_angles(const Vec3& p) {
  LegAngles a;
  EXPECT_TRUE(inverse(p, a)) << p.x << " " << p.y << " " << p.z;
  return a.t1;
}

// every point of an n^3 grid over the workspace cube (device frame)
template <class F>
void over_workspace(int n, F f) {
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const double s = 2.0 * kHalf_m / (n - 1);
        f(Vec3{-kHalf_m + i * s, -kHalf_m + j * s, kCentreZ_m - kHalf_m + k * s});
      }
    }
  }
}

TEST(FalconKinematics, ForwardOfInverseIsTheIdentityWithinOneMicrometre) {
  double worst = 0.0;
  int points = 0;
  over_workspace(11, [&](const Vec3& p) {
    const auto t1 = arm_angles(p);
    Vec3 back;
    // from the centre, as after homing, and warm-started from 10 mm away (a previous sample:
    // the grip never moves that far in the millisecond between two)
    for (const Vec3& guess : {Vec3{0.0, 0.0, kCentreZ_m}, p + Vec3{0.006, -0.006, 0.0057}}) {
      ASSERT_TRUE(forward(t1, guess, back)) << p.x << " " << p.y << " " << p.z;
      worst = std::max(worst, distance(back, p));
    }
    ++points;
  });
  std::printf("[ falcon ] %d points, worst round-trip error %.3g m\n", points, worst);
  EXPECT_LT(worst, 1e-6);
}

TEST(FalconKinematics, TheCentreIsSymmetricAndAngleRisesTowardsTheUser) {
  // on the z axis the three legs, 120 degrees apart, have the same arm angle
  const auto c = arm_angles({0.0, 0.0, kCentreZ_m});
  EXPECT_NEAR(c[0], c[1], 1e-12);
  EXPECT_NEAR(c[0], c[2], 1e-12);
  // pulling the grip out (towards the user, +z) opens every arm
  const auto out = arm_angles({0.0, 0.0, kCentreZ_m + 0.02});
  for (int i = 0; i < 3; ++i) EXPECT_GT(out[static_cast<std::size_t>(i)], c[static_cast<std::size_t>(i)]);
  // out of reach: refused, not garbage
  LegAngles a;
  EXPECT_FALSE(inverse({0.0, 0.0, 0.3}, a));
}

TEST(FalconKinematics, TheJacobianMatchesFiniteDifferences) {
  constexpr double h = 1e-7;
  double worst = 0.0;
  over_workspace(5, [&](const Vec3& p) {
    LegAngles a;
    ASSERT_TRUE(inverse(p, a));
    const Jacobian j = angle_jacobian(a);
    const Vec3 axes[3] = {{h, 0, 0}, {0, h, 0}, {0, 0, h}};
    for (int axis = 0; axis < 3; ++axis) {
      const auto plus = arm_angles(p + axes[axis]), minus = arm_angles(p - axes[axis]);
      for (int leg = 0; leg < 3; ++leg) {
        const auto l = static_cast<std::size_t>(leg);
        const double numeric = (plus[l] - minus[l]) / (2.0 * h);
        const double analytic = axis == 0 ? j[l].x : axis == 1 ? j[l].y : j[l].z;
        worst = std::max(worst, std::abs(numeric - analytic) / std::max(1.0, std::abs(numeric)));
      }
    }
  });
  std::printf("[ falcon ] worst Jacobian error against central differences %.3g (rad/m, relative above 1)\n", worst);
  EXPECT_LT(worst, 1e-5);
}

TEST(FalconKinematics, TorquesDoTheWorkOfTheForce) {
  // virtual work: for a small move dp, the joint torques' work tau . dt1 is the force's F . dp
  const Vec3 p{0.012, -0.018, kCentreZ_m + 0.01};
  LegAngles a;
  ASSERT_TRUE(inverse(p, a));
  const Jacobian j = angle_jacobian(a);
  for (const Vec3& f : {Vec3{3, 0, 0}, Vec3{0, -2, 0}, Vec3{0, 0, 5}, Vec3{1.5, 2.5, -4}}) {
    Vec3 tau;
    ASSERT_TRUE(torques(j, f, tau));
    for (const Vec3& dp : {Vec3{1e-7, 0, 0}, Vec3{0, 1e-7, 0}, Vec3{0, 0, 1e-7}, Vec3{3e-8, -5e-8, 4e-8}}) {
      const auto t0 = arm_angles(p - dp * 0.5), t1 = arm_angles(p + dp * 0.5);
      const double work_joints = tau.x * (t1[0] - t0[0]) + tau.y * (t1[1] - t0[1]) + tau.z * (t1[2] - t0[2]);
      EXPECT_NEAR(work_joints, math::dot(f, dp), 1e-6 * math::norm(f) * math::norm(dp));
    }
    // and the emulator's way back, F = J^T tau
    const Vec3 back = force_of(j, tau);
    EXPECT_NEAR(distance(back, f), 0.0, 1e-9);
  }
}

TEST(FalconKinematics, MotorCommandsFollowLibnifalconsScaleAndKeepTheirRatioWhenSaturated) {
  // -10000 per N m
  const auto m = motor_commands({0.1, -0.2, 0.05});
  EXPECT_EQ(m[0], -1000);
  EXPECT_EQ(m[1], 2000);
  EXPECT_EQ(m[2], -500);
  const Vec3 back = torques_of(m);
  EXPECT_NEAR(back.x, 0.1, 1e-12);
  // beyond int16: all three scaled by the same factor
  const auto s = motor_commands({6.0, -3.0, 1.5});
  EXPECT_EQ(s[0], -32767);
  EXPECT_NEAR(static_cast<double>(s[1]) / s[0], -0.5, 1e-4);
  EXPECT_NEAR(static_cast<double>(s[2]) / s[0], 0.25, 1e-4);
}

TEST(FalconKinematics, EncoderCountsFollowTheGeometry) {
  // 0.01425 m shaft, 320 slots x 4 edges, 0.110 m capstan: 0.0364347 degrees per count,
  // count 0 at 35 degrees
  constexpr double kDeg = std::numbers::pi / 180.0;
  EXPECT_NEAR(angle_of(0), 35.0 * kDeg, 1e-12);
  EXPECT_NEAR(angle_of(1000) - angle_of(0), 1000 * 0.01425 * 360.0 / (1280.0 * 0.110) * kDeg, 1e-12);
  for (int c : {-2000, -1, 0, 1, 777, 3000}) EXPECT_EQ(count_of(angle_of(static_cast<std::int16_t>(c))), c);
  EXPECT_EQ(count_of(100.0), 32767);
}

TEST(FalconKinematics, TheEnactFrameIsTheDeviceFrameTurnedAboutTheWorkspaceCentre) {
  // the workspace centre is the enact origin; device up is enact up; towards the user is enact -y
  EXPECT_EQ(to_enact({0.0, 0.0, kCentreZ_m}), (Vec3{0.0, 0.0, 0.0}));
  EXPECT_EQ(to_enact({0.0, 0.01, kCentreZ_m}), (Vec3{0.0, 0.0, 0.01}));
  EXPECT_NEAR(distance(to_enact({0.0, 0.0, kCentreZ_m + 0.01}), Vec3{0.0, -0.01, 0.0}), 0.0, 1e-15);
  EXPECT_EQ(to_enact({0.01, 0.0, kCentreZ_m}), (Vec3{0.01, 0.0, 0.0}));
  const Vec3 e{0.003, -0.02, 0.012};
  EXPECT_NEAR(distance(to_enact(to_device(e)), e), 0.0, 1e-15);
  EXPECT_EQ(direction_to_enact(direction_to_device(e)), e);
}

}  // namespace
}  // namespace enact::devices::falcon
