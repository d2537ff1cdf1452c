// The bridge's forces along the scripted hand path (enact path) are bit-identical to those
// of the engine before pair culling (commit 180236d): a checksum of every step's device
// force, contact flags and contact normals, stored here. The checksums hold for IEEE
// doubles on x86-64 without FMA contraction (the default build); another compiler or
// architecture may need them re-taken from the commit above.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "tests/physics/models.h"

namespace enact::physics {
namespace {

// FNV-1a over 64-bit words
struct Checksum {
  std::uint64_t value = 14695981039346656037ull;
  void add(std::uint64_t word) {
    for (int byte = 0; byte < 8; ++byte) {
      value ^= (word >> (8 * byte)) & 0xffu;
      value *= 1099511628211ull;
    }
  }
  void add(double d) { add(std::bit_cast<std::uint64_t>(d)); }
  void add(const Vec3& v) {
    add(v.x);
    add(v.y);
    add(v.z);
  }
};

// every step's force, contact flags and active contacts' normals and depths; `cull`: skip
// the pairs whose bounding volumes are apart (false: the unoptimised reference)
std::uint64_t run(const Model& m, const std::vector<Vec3>& motion, bool cull = true, long* culled = nullptr) {
  State s = make_state(m);
  s.cull = cull;
  Checksum sum;
  for (const Vec3& p : motion) {
    s.proxy_position_m[0] = p;
    step(m, s);
    if (culled) *culled += std::count(s.group_apart.begin(), s.group_apart.end(), std::uint8_t{1});
    sum.add(s.proxy_force_n[0]);
    for (const std::uint8_t c : s.in_contact) sum.add(std::uint64_t{c});
    for (const ContactState& c : s.contacts) {
      if (!c.active) continue;
      sum.add(c.normal);
      sum.add(c.depth_m);
    }
  }
  EXPECT_EQ(s.faults, 0u);
  return sum.value;
}

struct Case {
  double rate_hz;
  const char* computer_model;
  std::uint64_t checksum;
};

class Identical : public ::testing::TestWithParam<Case> {};

TEST_P(Identical, ForcesAlongTheScriptedPath) {
  const Case c = GetParam();
  EXPECT_EQ(run(models::bridge(c.rate_hz, c.computer_model), models::scripted_motion(c.rate_hz)), c.checksum);
}

INSTANTIATE_TEST_SUITE_P(Bridge, Identical,
                         ::testing::Values(Case{44000.0, "CM1", 0x7216ca7aa458fb52ull}, Case{5000.0, "CM1", 0x403f759621d9e1e2ull},
                                           Case{5000.0, "PT", 0x922b867db3f78995ull},
                                           // CM0 and CM3 take their force from the same 16 grid masses as
                                           // CM1 (they differ in pins only): CM1's checksum; CM2 (its 3 mm
                                           // threshold) taken on the branch that added the deformable body
                                           // (whose code leaves the rigid grid's step as it was)
                                           Case{5000.0, "CM0", 0x403f759621d9e1e2ull}, Case{5000.0, "CM3", 0x403f759621d9e1e2ull},
                                           Case{5000.0, "CM2", 0xa0ae36bfbc3cd996ull}),
                         [](const auto& p) { return std::string(p.param.computer_model) + "_" + std::to_string(static_cast<int>(p.param.rate_hz)); });

// a hand path through every group's transitions: from high above the floor beside the bridge
// down into the floor, sideways into the bridge's wall, up and onto the top, and away
std::vector<Vec3> floor_and_wall_motion(const Model& m, double rate_hz) {
  const models::Segment seg = models::bridge_segment(m, 0);
  const double half_width = m.objects[m.find_object("bridge")].path.width_m / 2;
  const double top = seg.middle.z;
  const auto beside = [&](double lateral_m, double z_m) { return Vec3{seg.middle.x, seg.middle.y, z_m} + seg.across * lateral_m; };
  const std::vector<Vec3> keys{beside(half_width + 0.008, 0.02), beside(half_width + 0.008, -0.001), beside(half_width + 0.002, -0.001),
                               beside(half_width + 0.002, top - 0.0001), beside(0.0, top - 0.0001), beside(0.0, 0.02)};
  std::vector<Vec3> motion;
  const int per_key = static_cast<int>(0.3 * rate_hz);
  for (std::size_t k = 0; k + 1 < keys.size(); ++k) {
    for (int n = 0; n < per_key; ++n) motion.push_back(keys[k] + (keys[k + 1] - keys[k]) * (static_cast<double>(n) / per_key));
  }
  return motion;
}

TEST(Culling, ChangesNothingThroughTheFloorAndTheWall) {
  for (const double rate_hz : {5000.0, 44000.0}) {
    const Model m = models::bridge(rate_hz);
    const std::vector<Vec3> motion = floor_and_wall_motion(m, rate_hz);
    long culled = 0;
    EXPECT_EQ(run(m, motion, true, &culled), run(m, motion, false)) << rate_hz << " Hz";
    EXPECT_GT(culled, 0) << "some groups were apart";
    EXPECT_LT(culled, 2 * static_cast<long>(motion.size())) << "not all of them always";
  }
}

}  // namespace
}  // namespace enact::physics
