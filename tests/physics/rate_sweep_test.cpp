// enact check --rate-sweep: a mass dropped onto a device held still (a contact link to the
// body's grid mass) is run through the three integrators at 1 .. 44 kHz; the force the device
// feels under the explicit schemes converges on the high-rate (cordis) reference as the rate
// rises (implicit Euler's numerical damping keeps it apart); a scene without a body is refused.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <sstream>
#include <string>

#include "tests/support/test_util.h"

namespace enact::physics {
namespace {

constexpr const char* kScene = R"(scene: drop on the hand
rate_hz: 5000
gravity_m_per_s2: [0, 0, -9.81]
masses: [{name: ball, mass_kg: 0.01, position_m: [0, 0, 0.004]}]
body: {name: finger, position_m: [0, 0, 0], grid: {rows: 1, cols: 1, pitch_m: 0.002}}
links:
  - {name: touch, type: contact, a: finger/r0c0, b: ball, stiffness_n_per_m: 2000, damping_n_s_per_m: 0.01, threshold_m: 0.002}
)";

struct Row {
  double ns = 0.0;
  double rms_n = 0.0;
  double max_n = 0.0;
};

// the sweep table's rows by "integrator kHz"
std::map<std::string, Row> sweep_rows(const std::string& out) {
  std::map<std::string, Row> rows;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    char name[32];
    double khz = 0.0, pins = 0.0;
    Row r;
    unsigned long long faults = 0;
    if (std::sscanf(line.c_str(), "%31s %lf %lf %lf %lf %lf %llu", name, &khz, &r.ns, &r.rms_n, &r.max_n, &pins, &faults) == 7) {
      rows[std::string(name) + " " + std::to_string(static_cast<int>(khz))] = r;
    }
  }
  return rows;
}

TEST(RateSweep, ExplicitSchemesConvergeOnTheReference) {
  enact::test::TempDir dir;
  const std::string scene = dir.file("drop.yaml");
  enact::test::write_file(scene, kScene);
  const auto result = enact::test::run(std::string(ENACT_CLI) + " check " + scene + " --rate-sweep");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::map<std::string, Row> rows = sweep_rows(result.out);
  ASSERT_EQ(rows.size(), 18u) << result.out;
  for (const char* integrator : {"cordis", "symplectic_euler"}) {
    const Row& slow = rows.at(std::string(integrator) + " 1");
    const Row& fast = rows.at(std::string(integrator) + " 44");
    EXPECT_GT(slow.rms_n, 0.0) << integrator;
    EXPECT_LT(fast.rms_n, 0.2 * slow.rms_n) << integrator;
    EXPECT_LE(fast.rms_n, fast.max_n) << integrator;
    EXPECT_GT(fast.ns, 0.0) << integrator;
  }
  EXPECT_GT(rows.at("implicit_euler 44").rms_n, 0.0);
}

TEST(RateSweep, SceneWithoutBodyIsRefused) {
  enact::test::TempDir dir;
  const std::string scene = dir.file("nobody.yaml");
  enact::test::write_file(scene, "masses: [{name: m, mass_kg: 0.01, position_m: [0, 0, 0]}]\n");
  const auto result = enact::test::run(std::string(ENACT_CLI) + " check " + scene + " --rate-sweep");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("no body"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("fix:"), std::string::npos) << result.err;
}

}  // namespace
}  // namespace enact::physics
