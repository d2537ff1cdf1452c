// Frictional contact (ContactPair::friction, step.cpp friction_force): a block on a plane
// pulled by a slowly rising force sticks until the pull reaches static * N and then slides
// against dynamic * N; a device body sliding on a plane feels the same law, on every point and
// in its resultant; a random walk over the bridge with friction gives the device no energy; a
// scene with friction zeroed gives the forces of the scene without it, bit for bit (the shipped
// scene's forces are those of main: identical_test.cpp); the scene key and its refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/physics/stability.h"
#include "tests/physics/models.h"
#include "tests/support/refusal.h"

namespace enact::physics {
namespace {

constexpr double kStatic = 0.6;
constexpr double kDynamic = 0.4;
constexpr double kFrictionStiffness_n_per_m = 2000.0;
constexpr Friction kFriction{kStatic, kDynamic, kFrictionStiffness_n_per_m};
// the stated tolerance on the friction force, relative to the Coulomb bound it should reach
constexpr double kTolerance = 0.02;

// --- a block on a plane, pulled by a spring whose far end moves slowly: a rising pull ---

constexpr double kBlock_kg = 0.1;
constexpr double kGravity_m_per_s2 = 9.81;
constexpr double kLoad_n = kBlock_kg * kGravity_m_per_s2;  // the block's weight: its normal load
constexpr double kPlaneStiffness_n_per_m = 2000.0;
constexpr double kPullStiffness_n_per_m = 20.0;
constexpr double kHandSpeed_m_per_s = 0.005;  // the pull rises by 0.1 N/s

struct Block {
  Model model;
  int block = -1;
  int hand = -1;
};

// the block rests at its static depth in the plane; the hand (proxy 0) holds the pull spring
Block block_on_plane(Integrator integrator, double rate_hz) {
  Block b;
  Model& m = b.model;
  m.integrator = integrator;
  m.set_rate(rate_hz);
  m.gravity_m_per_s2 = {0, 0, -kGravity_m_per_s2};
  const Vec3 rest{0, 0, -kLoad_n / kPlaneStiffness_n_per_m};
  b.block = models::add_point(m, "block", PointKind::dynamic, rest, kBlock_kg);
  b.hand = models::add_point(m, "hand", PointKind::kinematic, rest);
  m.points[b.hand].proxy = 0;
  m.proxies.push_back({"hand", b.hand, -1, 0, 0, 0.0, 0});
  models::add_link(m, "pull", LinkType::spring, b.hand, b.block, kPullStiffness_n_per_m, 0.0);
  models::add_contact(m, b.block, models::add_plane(m, "floor", {}, {0, 0, 1}), kPlaneStiffness_n_per_m, 1.0);
  m.contacts[0].friction = kFriction;
  return b;
}

// one step's forces on the block, from the force balance (the step's force minus gravity and
// the pull, at the positions the step used): the plane's normal force and its friction along x
struct BlockForces {
  double pull_n = 0.0;
  double normal_n = 0.0;
  double friction_n = 0.0;
  double displacement_m = 0.0;  // of the block along x at that step
  double speed_m_per_s = 0.0;   // the block's velocity along x after it
};

BlockForces block_forces(const Block& b, const State& s) {
  const Vec3 at = s.x_prev[b.block];  // x(n): the position the step's forces were taken at
  const Vec3 pull = (s.x[b.hand] - at) * kPullStiffness_n_per_m;
  const Vec3 contact = s.f[b.block] - pull + Vec3{0, 0, kLoad_n};
  return {pull.x, contact.z, contact.x, at.x, s.v[b.block].x};
}

struct BlockCase {
  Integrator integrator;
  double rate_hz;
};

// (implicit_euler is left out: its per-mass stiffness acts in every direction, so the plane's
// stiffness drags the sliding block by dt k and it creeps along instead of coming to rest)
class BlockPulled : public ::testing::TestWithParam<BlockCase> {};

TEST_P(BlockPulled, SticksUntilStaticThenSlidesAgainstDynamic) {
  const double rate_hz = GetParam().rate_hz;
  const Block b = block_on_plane(GetParam().integrator, rate_hz);
  State s = make_state(b.model);
  const double stuck_m = kStatic * kLoad_n / kFrictionStiffness_n_per_m;  // the stiction spring's compliance
  const long steps = std::lround(7.0 * rate_hz);
  double breakaway_pull_n = -1.0;
  int sliding_steps = 0;
  bool first_slip_over = false;
  for (long n = 0; n < steps && !first_slip_over; ++n) {
    s.proxy_position_m[0] = Vec3{kHandSpeed_m_per_s * static_cast<double>(n) / rate_hz, 0, 0} + b.model.points[b.hand].position_m;
    step(b.model, s);
    const BlockForces f = block_forces(b, s);
    ASSERT_NEAR(f.normal_n, kLoad_n, 1e-3 * kLoad_n) << "step " << n;
    if (breakaway_pull_n < 0.0) {
      // stuck: the friction balances the pull and the block moves no farther than the
      // stiction spring's compliance; the first step on which either fails is the breakaway
      const bool stuck = f.displacement_m <= stuck_m * (1.0 + 1e-6) && std::abs(f.friction_n + f.pull_n) <= kTolerance * kStatic * kLoad_n;
      if (!stuck) breakaway_pull_n = f.pull_n;
      continue;
    }
    // the first slip, while the block moves on: friction at the dynamic bound, against it
    first_slip_over = f.speed_m_per_s <= 0.0;
    if (f.speed_m_per_s < 0.01) continue;
    ++sliding_steps;
    ASSERT_NEAR(f.friction_n, -kDynamic * kLoad_n, kTolerance * kDynamic * kLoad_n) << "step " << n << ", speed " << f.speed_m_per_s;
  }
  EXPECT_EQ(s.faults, 0u);
  EXPECT_NEAR(breakaway_pull_n, kStatic * kLoad_n, kTolerance * kStatic * kLoad_n) << "it broke away at another pull";
  EXPECT_TRUE(first_slip_over) << "the block came to rest again";
  EXPECT_GT(sliding_steps, static_cast<int>(0.05 * rate_hz)) << "it slid for at least 50 ms";
}

INSTANTIATE_TEST_SUITE_P(Rates, BlockPulled,
                         ::testing::Values(BlockCase{Integrator::cordis, 1000.0}, BlockCase{Integrator::cordis, 5000.0},
                                           BlockCase{Integrator::cordis, 44000.0}, BlockCase{Integrator::symplectic_euler, 1000.0}),
                         [](const auto& p) { return std::string(to_string(p.param.integrator)) + "_" + std::to_string(static_cast<int>(p.param.rate_hz)); });

// --- a device body pressed into a plane and slid along it, then back ---

constexpr double kPress_m = 0.0005;
constexpr double kBodyContact_n_per_m = 6000.0;
constexpr double kPointLoad_n = kBodyContact_n_per_m * kPress_m;  // each grid point's normal force

// a 2 x 2 body pressed kPress_m into a plane, its four grid points in frictional contact
Model body_on_plane(double rate_hz) {
  Model m;
  m.set_rate(rate_hz);
  models::add_body(m, {0, 0, -kPress_m}, 2, 2);
  const int floor = models::add_plane(m, "floor", {}, {0, 0, 1});
  for (int i = 0; i < 4; ++i) models::add_contact(m, m.proxies[0].first_body + i, floor, kBodyContact_n_per_m, 0.02);
  models::add_friction(m, kFriction);
  return m;
}

// the force on the first grid point along `along`; every grid point feels the same
double point_friction_n(const Model& m, const State& s, const Vec3& along) {
  const Proxy& p = m.proxies[0];
  const double first = dot(s.f[p.first_body], along);
  for (int i = 1; i < 4; ++i) EXPECT_NEAR(dot(s.f[p.first_body + i], along), first, 1e-12);
  return first;
}

class BodySlid : public ::testing::TestWithParam<double> {};

TEST_P(BodySlid, TheDeviceFeelsStictionThenSliding) {
  const double rate_hz = GetParam();
  const Model m = body_on_plane(rate_hz);
  State s = make_state(m);
  const Vec3 along{0.6, 0.8, 0.0};
  constexpr double kSpeed_m_per_s = 0.02, kTravel_m = 0.002;
  const double step_m = kSpeed_m_per_s / rate_hz;
  const double hold_m = kStatic * kPointLoad_n / kFrictionStiffness_n_per_m;                   // stuck before the slide
  const double turn_m = (kStatic + kDynamic) * kPointLoad_n / kFrictionStiffness_n_per_m;     // stuck after turning back
  const long out = std::lround(kTravel_m / step_m);
  int stuck = 0, slid = 0;
  for (long n = 0; n <= 2 * out; ++n) {
    // out along `along`, then back: `from` is how far the body is from where it last turned
    const bool back = n > out;
    const double from = static_cast<double>(back ? n - out : n) * step_m;
    s.proxy_position_m[0] = Vec3{0, 0, -kPress_m} + along * (static_cast<double>(back ? 2 * out - n : n) * step_m);
    step(m, s);
    const double sign = back ? -1.0 : 1.0;  // the direction of motion along `along`
    const double f = point_friction_n(m, s, along) * sign;  // positive: with the motion
    EXPECT_NEAR(dot(s.proxy_force_n[0], along), 4.0 * point_friction_n(m, s, along), 1e-12) << "step " << n;
    EXPECT_NEAR(s.proxy_force_n[0].z, 4.0 * kPointLoad_n, 1e-9) << "step " << n;
    const double limit_m = back ? turn_m : hold_m;
    if (from < limit_m - step_m) {
      // stuck: the anchor spring stretches with the body (before the turn from the dynamic
      // bound it held, after it from the static bound the other way)
      const double expected_n = back ? kDynamic * kPointLoad_n - kFrictionStiffness_n_per_m * from : -kFrictionStiffness_n_per_m * from;
      EXPECT_NEAR(f, expected_n, 1e-9) << "step " << n;
      ++stuck;
    } else if (from > limit_m + step_m) {
      EXPECT_NEAR(f, -kDynamic * kPointLoad_n, kTolerance * kDynamic * kPointLoad_n) << "step " << n;
      ++slid;
    }
    EXPECT_GE(f, -kStatic * kPointLoad_n * (1.0 + kTolerance)) << "step " << n << ": more than the static bound";
  }
  EXPECT_GT(stuck, 0);
  EXPECT_GT(slid, 0);
  EXPECT_EQ(s.faults, 0u);
}

INSTANTIATE_TEST_SUITE_P(Rates, BodySlid, ::testing::Values(1000.0, 5000.0, 44000.0),
                         [](const auto& p) { return std::to_string(static_cast<int>(p.param)) + "Hz"; });

// --- passivity: a random walk of the device over the bridge ---

// rounding of the summed work over a walk (J): forces of ~100 N over ~10^4 steps of ~0.1 mm
constexpr double kWorkTolerance_j = 1e-9;

// the work the contacts do on the device along `path`, from rest at its start
double walk_work_j(const Model& m, const std::vector<Vec3>& path) {
  State s = make_state(m);
  models::place_body(m, s, path.front());
  const double work_j = models::device_work_j(m, s, path);
  EXPECT_EQ(s.faults, 0u);
  return work_j;
}

struct WalkCase {
  double rate_hz;
  unsigned seed;
};

class FrictionWalk : public ::testing::TestWithParam<WalkCase> {};

// the device never gets energy from the contacts with friction on (beyond rounding). The body
// is kinematic, so the normal forces are the same with friction and without: the difference
// of the two works is the work of friction alone, and it is negative (it slid: friction took
// energy, at least a millijoule) and never positive
TEST_P(FrictionWalk, TheDeviceGetsNoEnergy) {
  const Model without = models::bridge(GetParam().rate_hz);
  Model with = without;
  models::add_friction(with, kFriction);
  const std::vector<Vec3> path = models::walk_over_the_bridge(with, GetParam().seed, 10.0);
  const double with_j = walk_work_j(with, path), without_j = walk_work_j(without, path);
  std::printf("work on the device: %.6g J with friction, %.6g J without\n", with_j, without_j);
  EXPECT_LE(with_j, kWorkTolerance_j);
  EXPECT_LT(with_j - without_j, -1e-3) << "friction took energy";
}

INSTANTIATE_TEST_SUITE_P(Bridge, FrictionWalk,
                         ::testing::Values(WalkCase{1000.0, 1}, WalkCase{5000.0, 2}, WalkCase{5000.0, 3}),
                         [](const auto& p) { return std::to_string(static_cast<int>(p.param.rate_hz)) + "Hz_seed" + std::to_string(p.param.seed); });

// --- friction off: the forces of the scene without it, bit for bit ---

// the shipped bridge scene with `friction` (YAML) on its contact entry, written to `dir`
std::string bridge_with_friction(const enact::test::TempDir& dir, const std::string& friction) {
  YAML::Node root = YAML::LoadFile(enact::test::source_path("launch/scenes/bridge.yaml"));
  root["contacts"][0]["friction"] = YAML::Load(friction);
  YAML::Emitter out;
  out << root;
  const std::string path = dir.file("bridge.yaml");
  enact::test::write_file(path, out.c_str());
  return path;
}

// steps along the scripted path on which the forces of `a` and `b` differ in any bit: the
// device's, or any point's
long differing_steps(const Model& a, const Model& b, const std::vector<Vec3>& motion) {
  State sa = make_state(a), sb = make_state(b);
  long differing = 0;
  for (const Vec3& p : motion) {
    sa.proxy_position_m[0] = sb.proxy_position_m[0] = p;
    step(a, sa);
    step(b, sb);
    bool same = models::same_bits(sa.proxy_force_n[0], sb.proxy_force_n[0]);
    for (std::size_t i = 0; i < sa.f.size(); ++i) same = same && models::same_bits(sa.f[i], sb.f[i]);
    differing += !same;
  }
  return differing;
}

// zero coefficients: the anchor spring never holds a force, and the forces are those of the
// scene without the key (which are main's: identical_test.cpp); with friction they differ
TEST(FrictionOff, ZeroedFrictionGivesTheForcesOfTheSceneWithoutIt) {
  constexpr double kRate_hz = 5000.0;
  const enact::test::TempDir dir;
  const Model without = models::bridge(kRate_hz);
  const Model zeroed = models::bridge(kRate_hz, "CM1", bridge_with_friction(dir, "{static: 0, dynamic: 0, stiffness_n_per_m: 2000}"));
  const Model with = models::bridge(kRate_hz, "CM1", bridge_with_friction(dir, "{static: 0.6, dynamic: 0.4, stiffness_n_per_m: 2000}"));
  for (const ContactPair& c : without.contacts) EXPECT_FALSE(c.friction.enabled());
  for (const ContactPair& c : zeroed.contacts) EXPECT_TRUE(c.friction.enabled());
  const std::vector<Vec3> motion = models::scripted_motion(kRate_hz);
  EXPECT_EQ(differing_steps(without, zeroed, motion), 0);
  EXPECT_GT(differing_steps(without, with, motion), static_cast<long>(motion.size()) / 10) << "friction acts on the scripted path";
}

// --- stability: a pair is as stiff as the stiffer of its contact and anchor springs ---

// a 10 g mass at 1 kHz (explicit bound 4M = 40000 N/m) on a 20000 N/m plane: an anchor spring
// softer than the contact adds nothing, a stiffer one counts as itself, past the bound refused
TEST(FrictionStability, APairCountsAsTheStifferOfItsTwoSprings) {
  for (const double anchor_n_per_m : {10000.0, 30000.0, 45000.0}) {
    Model m;
    m.source = "s.yaml";
    m.set_rate(1000.0);
    const int mass = models::add_point(m, "ball", PointKind::dynamic, {}, 0.01);
    models::add_contact(m, mass, models::add_plane(m, "floor", {}, {0, 0, 1}), 20000.0, 0.0);
    m.contacts[0].friction = {kStatic, kDynamic, anchor_n_per_m};
    const StabilityReport r = analyze_stability(m);
    EXPECT_EQ(r.masses[0].stiffness_n_per_m, std::max(20000.0, anchor_n_per_m)) << anchor_n_per_m;
    EXPECT_EQ(r.stable(), anchor_n_per_m < 40000.0) << anchor_n_per_m;
    const std::string message = instability_message(m, r);
    EXPECT_EQ(message.find("lower the stiffness of friction of 'ball' with 'floor'") != std::string::npos, !r.stable()) << message;
  }
}

// --- the scene key ---

std::string scene_with_contact(const std::string& contact) {
  return "masses: [{name: block, mass_kg: 0.1, position_m: [0, 0, 0.001]}]\n"
         "objects: [{name: floor, type: plane, normal: [0, 0, 1]}]\n"
         "contacts:\n"
         "  - {masses: [block], objects: [floor], stiffness_n_per_m: 2000}\n"
         "  - masses: [block]\n"
         "    objects: [floor]\n"
         "    stiffness_n_per_m: 2000\n" +
         contact;
}

TEST(FrictionScene, TheKeyIsReadForEachPairOfItsEntry) {
  const enact::test::TempDir dir;
  const std::string path = dir.file("s.yaml");
  enact::test::write_file(path, scene_with_contact("    friction: {static: 0.6, dynamic: 0.4, stiffness_n_per_m: 2000}\n"));
  const Model m = load_scene(path);
  ASSERT_EQ(m.contacts.size(), 2u);
  EXPECT_FALSE(m.contacts[0].friction.enabled());
  EXPECT_EQ(m.contacts[1].friction.static_coeff, 0.6);
  EXPECT_EQ(m.contacts[1].friction.dynamic_coeff, 0.4);
  EXPECT_EQ(m.contacts[1].friction.stiffness_n_per_m, 2000.0);
}

struct Refusal {
  const char* name;
  const char* friction;  // the friction line
  const char* problem;   // what the message must say
};

class FrictionRefused : public ::testing::TestWithParam<Refusal> {};

// each refusal names the file, the friction line (line 8) and a fix
TEST_P(FrictionRefused, NamesTheFileTheLineAndTheFix) {
  const std::string text = scene_with_contact(std::string("    friction: ") + GetParam().friction + "\n");
  const std::string error = enact::test::error_of_file("s.yaml", text, [](const std::string& path) { load_scene(path); });
  EXPECT_NE(error.find("s.yaml:8: "), std::string::npos) << error;
  EXPECT_NE(error.find(GetParam().problem), std::string::npos) << error;
  EXPECT_NE(error.find("\n  fix: "), std::string::npos) << error;
}

INSTANTIATE_TEST_SUITE_P(
    Scene, FrictionRefused,
    ::testing::Values(Refusal{"DynamicAboveStatic", "{static: 0.4, dynamic: 0.6, stiffness_n_per_m: 2000}", "dynamic (0.6) is above static (0.4)"},
                      Refusal{"ZeroStiffness", "{static: 0.6, dynamic: 0.4, stiffness_n_per_m: 0}", "stiffness_n_per_m must be > 0"},
                      Refusal{"NegativeCoefficient", "{static: 0.6, dynamic: -0.1, stiffness_n_per_m: 2000}", "dynamic must be >= 0"},
                      Refusal{"MissingKey", "{static: 0.6, stiffness_n_per_m: 2000}", "needs dynamic"},
                      Refusal{"UnknownKey", "{static: 0.6, dynamic: 0.4, stiffness: 2000}", "unknown key 'stiffness'"},
                      Refusal{"NotAMapping", "0.5", "must be a mapping"}),
    [](const auto& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace enact::physics
