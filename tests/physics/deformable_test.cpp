// The deformable fingertip (scene key body.deformable): each grid mass has its own dynamics,
// tied to its rest place on the proxy and to its grid neighbours by linear visco-elastic
// links; the device feels the proxy links' pull. Pressed statically on a box it reaches the
// analytic equilibrium (the coupling force equals the contact force); over an edge only the
// masses over the box touch and the others hang at their rest place (pulled up by their
// neighbours by what the linear equilibrium says); friction slides, sticks and stick-slips; the
// explicit step bound of enact check holds just inside and fails just outside; the scene keys
// are validated with file:line errors.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/physics/stability.h"
#include "core/sim/params.h"
#include "core/sim/simulator.h"
#include "tests/physics/models.h"
#include "tests/support/refusal.h"

namespace enact::physics {
namespace {

constexpr double kMass_kg = 0.0005;
constexpr double kProxyK_n_per_m = 2000.0, kProxyZ_n_s_per_m = 0.15;
constexpr double kGridK_n_per_m = 500.0, kGridZ_n_s_per_m = 0.05;
constexpr double kContactK_n_per_m = 6000.0, kContactZ_n_s_per_m = 0.02;
constexpr double kTop_m = 0.01;
constexpr double kDepth_m = 0.0005;  // how far below the top the proxy presses
constexpr int kMasses = 16;

DeformableBody fingertip(double grid_k = kGridK_n_per_m, double grid_z = kGridZ_n_s_per_m) {
  return {.mass_kg = kMass_kg,
          .proxy_stiffness_n_per_m = kProxyK_n_per_m,
          .proxy_damping_n_s_per_m = kProxyZ_n_s_per_m,
          .grid_stiffness_n_per_m = grid_k,
          .grid_damping_n_s_per_m = grid_z};
}

// a deformable 4 x 4 body 2 mm above a box whose top is at kTop_m and which covers x < edge_x_m
Model over_box(Integrator integrator, const DeformableBody& body, double edge_x_m = 1.0) {
  Model m;
  m.name = "deformable";
  m.source = "deformable.yaml";
  m.integrator = integrator;
  m.set_rate(5000.0);
  models::add_body(m, {0, 0, kTop_m + 0.002});
  m.make_deformable(0, body);
  const double half = 0.03;
  const int box = models::add_boxes(m, "box", {{{std::min(edge_x_m, 0.02) - half, 0, kTop_m - half}, {half, half, half}}});
  for (int i = 0; i < kMasses; ++i) models::add_contact(m, m.proxies[0].first_body + i, box, kContactK_n_per_m, kContactZ_n_s_per_m);
  m.index_boxes();
  return m;
}

// lower the proxy from where it starts to kDepth_m below the top over 0.1 s, then hold it 0.5 s
State press(const Model& m) {
  State s = make_state(m);
  const Vec3 from = s.proxy_position_m[0], to{0, 0, kTop_m - kDepth_m};
  const long lower = std::lround(0.1 * m.rate_hz), hold = std::lround(0.5 * m.rate_hz);
  for (long n = 1; n <= lower + hold; ++n) {
    s.proxy_position_m[0] = from + (to - from) * (static_cast<double>(std::min(n, lower)) / static_cast<double>(lower));
    step(m, s);
  }
  EXPECT_EQ(s.faults, 0u);
  return s;
}

Vec3 contact_sum(const Model& m, const State& s) {
  Vec3 sum;
  for (int i = 0; i < kMasses; ++i) sum += body_contact_force(m, s, m.proxies[0].first_body + i);
  return sum;
}

class StaticPress : public ::testing::TestWithParam<Integrator> {};

// every mass sinks p = k_p d / (k_p + k_c) into the box (the proxy link and the contact in
// series; the grid links carry nothing), and the device feels 16 k_p k_c d / (k_p + k_c), the
// sum of the contact forces
TEST_P(StaticPress, ReachesTheAnalyticEquilibrium) {
  const Model m = over_box(GetParam(), fingertip());
  const State s = press(m);
  const double sink_m = kProxyK_n_per_m * kDepth_m / (kProxyK_n_per_m + kContactK_n_per_m);
  const double force_n = kMasses * kProxyK_n_per_m * kContactK_n_per_m * kDepth_m / (kProxyK_n_per_m + kContactK_n_per_m);
  for (int i = 0; i < kMasses; ++i) {
    const int q = m.proxies[0].first_body + i;
    EXPECT_NEAR(s.x[q].z, kTop_m - sink_m, 1e-12) << m.points[q].name;
    EXPECT_TRUE(s.in_contact[q]);
  }
  const Vec3 device = s.proxy_force_n[0], contacts = contact_sum(m, s);
  EXPECT_NEAR(device.z, force_n, 1e-9 * force_n);
  EXPECT_NEAR(norm(device - contacts), 0.0, 1e-9 * force_n) << "the coupling force is the contact force at rest";
  EXPECT_NEAR(std::hypot(device.x, device.y), 0.0, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Integrators, StaticPress,
                         ::testing::Values(Integrator::cordis, Integrator::symplectic_euler, Integrator::implicit_euler),
                         [](const auto& p) { return std::string(to_string(p.param)); });

// the linear equilibrium of the masses' heights with the masses in `touching` on the top:
// (k_p + n k_n + c k_c) z_i - k_n (sum of the neighbours' z) = k_p z_proxy + c k_c top
std::array<double, kMasses> equilibrium_heights(const Proxy& p, double grid_k, std::uint32_t touching) {
  std::array<std::array<double, kMasses + 1>, kMasses> a{};
  for (int i = 0; i < kMasses; ++i) {
    const int r = i / p.cols, c = i % p.cols;
    const bool on = (touching >> i) & 1u;
    a[i][i] = kProxyK_n_per_m + (on ? kContactK_n_per_m : 0.0);
    a[i][kMasses] = kProxyK_n_per_m * (kTop_m - kDepth_m) + (on ? kContactK_n_per_m * kTop_m : 0.0);
    const int neighbours[4][2] = {{r - 1, c}, {r + 1, c}, {r, c - 1}, {r, c + 1}};
    for (const auto& n : neighbours) {
      if (n[0] < 0 || n[0] >= p.rows || n[1] < 0 || n[1] >= p.cols) continue;
      a[i][i] += grid_k;
      a[i][n[0] * p.cols + n[1]] -= grid_k;
    }
  }
  // Gaussian elimination (the matrix is symmetric positive definite: no pivoting needed)
  for (int k = 0; k < kMasses; ++k) {
    for (int i = k + 1; i < kMasses; ++i) {
      const double f = a[i][k] / a[k][k];
      for (int j = k; j <= kMasses; ++j) a[i][j] -= f * a[k][j];
    }
  }
  std::array<double, kMasses> z{};
  for (int i = kMasses - 1; i >= 0; --i) {
    double rhs = a[i][kMasses];
    for (int j = i + 1; j < kMasses; ++j) rhs -= a[i][j] * z[j];
    z[i] = rhs / a[i][i];
  }
  return z;
}

// the body's left half (columns 0 and 1, x < 0) over the box, its right half beyond the edge
constexpr std::uint32_t kLeftHalf = 0x3333;

// without grid links the masses beyond the edge hang exactly at their rest place and the
// others sink as on a full box; only the masses over the box touch, and only their pins rise
TEST(Edge, WithoutGridLinksTheMassesBeyondHangAtRest) {
  Model m = over_box(Integrator::cordis, fingertip(0.0, 0.0), 0.0);
  haptics::apply(*haptics::preset("CM1"), m);
  const State s = press(m);
  const Proxy& p = m.proxies[0];
  const double sink_m = kProxyK_n_per_m * kDepth_m / (kProxyK_n_per_m + kContactK_n_per_m);
  for (int i = 0; i < kMasses; ++i) {
    const int q = p.first_body + i;
    const bool over = (kLeftHalf >> i) & 1u;
    EXPECT_EQ(s.in_contact[q] != 0, over) << m.points[q].name;
    const Vec3 rest = s.proxy_position_m[0] + m.points[q].offset_m;
    if (over) EXPECT_NEAR(s.x[q].z, kTop_m - sink_m, 1e-12) << m.points[q].name;
    else EXPECT_NEAR(norm(s.x[q] - rest), 0.0, 1e-15) << m.points[q].name;
  }
  EXPECT_EQ(haptics::pins(*haptics::preset("CM1"), m, s), kLeftHalf);
}

// with grid links the heights are the linear equilibrium's: the masses beyond the edge are
// pulled up by their neighbours (the column next to the edge more than the far one), the
// column at the edge is pulled down by them (sinks deeper than the column behind it)
TEST(Edge, WithGridLinksTheHeightsAreTheLinearEquilibrium) {
  const Model m = over_box(Integrator::cordis, fingertip(), 0.0);
  const State s = press(m);
  const Proxy& p = m.proxies[0];
  const std::array<double, kMasses> z = equilibrium_heights(p, kGridK_n_per_m, kLeftHalf);
  for (int i = 0; i < kMasses; ++i) {
    const int q = p.first_body + i;
    EXPECT_EQ(s.in_contact[q] != 0, ((kLeftHalf >> i) & 1u) != 0) << m.points[q].name;
    EXPECT_NEAR(s.x[q].z, z[i], 1e-12) << m.points[q].name;
  }
  const double rest = kTop_m - kDepth_m;
  const auto height = [&](int col) { return s.x[p.first_body + p.cols + col].z; };
  EXPECT_GT(height(3) - rest, 1e-6) << "the far column is pulled up";
  EXPECT_GT(height(2), height(3)) << "the column beyond the edge more";
  EXPECT_LT(height(1), height(0)) << "the column at the edge sinks deeper";
  EXPECT_NEAR(norm(s.proxy_force_n[0] - contact_sum(m, s)), 0.0, 1e-9);
}

// friction through the deformable body, the masses pressed 0.5 mm into a box and the proxy
// moved `travel_m` along x at 10 mm/s, then held `hold_s`; the device force at the end, and
// over the last 0.2 s of the move the mean of fx / fz and how many steps each contact slid
struct Drag {
  Vec3 force_n;
  double mean_ratio = 0.0;
  int always_sliding = 0, never_sliding = 0;  // contacts over the last 0.2 s
};

Drag drag(const Friction& friction, double travel_m, double hold_s = 0.0) {
  Model m = over_box(Integrator::cordis, fingertip());
  models::add_friction(m, friction);
  State s = press(m);
  const Vec3 pressed = s.proxy_position_m[0];
  const long steps = std::lround(travel_m / 0.01 * m.rate_hz), window = std::lround(0.2 * m.rate_hz);
  std::vector<int> slid(m.contacts.size(), 0);
  Drag d;
  for (long n = 1; n <= steps; ++n) {
    s.proxy_position_m[0] = pressed + Vec3{0.01 * static_cast<double>(n) * m.dt_s, 0, 0};
    step(m, s);
    if (n <= steps - window) continue;
    d.mean_ratio += s.proxy_force_n[0].x / s.proxy_force_n[0].z / static_cast<double>(window);
    for (std::size_t k = 0; k < slid.size(); ++k) slid[k] += s.contacts[k].sliding;
  }
  for (const int n : slid) {
    d.always_sliding += n == window;
    d.never_sliding += n == 0;
  }
  for (long n = 0; n < std::lround(hold_s * m.rate_hz); ++n) step(m, s);
  for (const ContactState& c : s.contacts) d.never_sliding -= hold_s > 0.0 && c.sliding;
  d.force_n = s.proxy_force_n[0];
  EXPECT_EQ(s.faults, 0u);
  return d;
}

// dragged at 10 mm/s with one coefficient every mass slides and the device feels it times the
// normal force (nothing else acts on a mass moving at constant speed)
TEST(Friction, SlidesThroughTheLinks) {
  const Drag d = drag({0.4, 0.4, 2000.0}, 0.003);
  EXPECT_NEAR(d.force_n.x / d.force_n.z, -0.4, 1e-6);
  EXPECT_EQ(d.always_sliding, kMasses);
}

// moved 0.05 mm and held every mass sticks: each proxy link and anchor spring in series, the
// device feels 16 k_p k_f / (k_p + k_f) times the move at rest
TEST(Friction, SticksThroughTheLinks) {
  const Drag d = drag({0.6, 0.4, 2000.0}, 0.00005, 0.5);
  EXPECT_EQ(d.never_sliding, kMasses);
  const double series = kProxyK_n_per_m * 2000.0 / (kProxyK_n_per_m + 2000.0);
  EXPECT_NEAR(d.force_n.x, -kMasses * series * 0.00005, 1e-12);
}

// with a static coefficient above the dynamic one a mass on its proxy link stick-slips (the
// classic spring-block oscillation): each contact both sticks and slides, and the mean force
// lies between the two coefficients times the normal force
TEST(Friction, StickSlipsThroughTheLinks) {
  const Drag d = drag({0.6, 0.4, 2000.0}, 0.003);
  EXPECT_EQ(d.always_sliding, 0);
  EXPECT_EQ(d.never_sliding, 0);
  EXPECT_LT(d.mean_ratio, -0.4);
  EXPECT_GT(d.mean_ratio, -0.6);
}

// --- the step bound: dt < 4m / (z + sqrt(z^2 + 4 K m)) ---

// the bound enact check gives, for the body in free space: at an inner mass (four grid
// neighbours), K = k_p + 8 k_n and z = z_p + 8 z_n
TEST(Bound, IsTheFormulaAtTheInnerMasses) {
  Model m = over_box(Integrator::cordis, fingertip());
  m.contacts.clear();
  const StabilityReport r = analyze_stability(m);
  ASSERT_EQ(r.bodies.size(), 1u);
  const double k = kProxyK_n_per_m + 8 * kGridK_n_per_m, z = kProxyZ_n_s_per_m + 8 * kGridZ_n_s_per_m;
  const double bound_s = 4 * kMass_kg / (z + std::sqrt(z * z + 4 * k * kMass_kg));
  EXPECT_NEAR(r.bodies[0].max_step_s, bound_s, 1e-12 * bound_s);
  EXPECT_EQ(m.points[r.bodies[0].point].name, "finger/r1c1");
  // undamped: 2 sqrt(m/K)
  m.make_deformable(0, fingertip(kGridK_n_per_m, 0.0));
  m.proxies[0].deformable.proxy_damping_n_s_per_m = 0.0;
  EXPECT_NEAR(analyze_stability(m).bodies[0].max_step_s, 2 * std::sqrt(kMass_kg / k), 1e-12);
}

// the largest displacement of the masses from their rest places over `steps` steps at
// `rate_hz`, the masses started at 0.01 m/s up and down in a checkerboard (the grid's fastest
// mode), the body `lower_m` below its scene position (-1 when the divergence guard tripped)
double ring(Model m, double rate_hz, long steps, double lower_m = 0.0) {
  m.set_rate(rate_hz);
  const Proxy& p = m.proxies[0];
  m.points[p.point].position_m.z -= lower_m;
  for (int i = 0; i < kMasses; ++i) m.points[p.first_body + i].velocity_m_per_s = {0, 0, (i / p.cols + i % p.cols) % 2 ? 0.01 : -0.01};
  State s = make_state(m);
  double most = 0.0;
  for (long n = 0; n < steps && s.faults == 0; ++n) {
    step(m, s);
    for (int i = 0; i < kMasses; ++i) {
      const int q = m.proxies[0].first_body + i;
      most = std::max(most, norm(s.x[q] - s.proxy_position_m[0] - m.points[q].offset_m));
    }
  }
  return s.faults == 0 ? most : -1.0;
}

// without grid links each mass is one damped oscillator on its proxy link and the bound is
// exact: at 97 % of it the masses ring and stay within their first swing; at 103 % they diverge
// and the guard trips; enact check says which
TEST(Bound, ExactForAMassOnItsProxyLink) {
  Model m = over_box(Integrator::cordis, fingertip(0.0, 0.0));
  m.contacts.clear();
  const double bound_s = analyze_stability(m).bodies[0].max_step_s;
  const double swing_m = 0.01 * std::sqrt(kMass_kg / kProxyK_n_per_m);  // v / omega
  for (const Integrator integrator : {Integrator::cordis, Integrator::symplectic_euler}) {
    m.integrator = integrator;
    const double inside = ring(m, 1.0 / (0.97 * bound_s), 200000);
    EXPECT_GE(inside, 0.0) << to_string(integrator);
    EXPECT_LT(inside, 3.0 * swing_m) << to_string(integrator);
    EXPECT_EQ(ring(m, 1.0 / (1.03 * bound_s), 200000), -1.0) << to_string(integrator);
    m.set_rate(1.0 / (1.03 * bound_s));
    EXPECT_FALSE(analyze_stability(m).stable());
    m.set_rate(1.0 / (0.97 * bound_s));
    EXPECT_TRUE(analyze_stability(m).stable());
  }
}

// with grid links and contacts the bound is sufficient (Gershgorin): the shipped scene, its
// body pressed 0.3 mm into the bridge's top, at 97 % of it rings without a fault; at 1.5
// times enact check refuses it, naming the file, the line of body.deformable and the fix,
// and it diverges
TEST(Bound, TheShippedSceneJustInsideAndOutside) {
  Model m = load_scene(enact::test::source_path("launch/scenes/bridge_deformable.yaml"));
  const StabilityReport at_5k = analyze_stability(m);
  ASSERT_EQ(at_5k.bodies.size(), 1u);
  EXPECT_TRUE(at_5k.stable());
  const double bound_s = at_5k.bodies[0].max_step_s;
  EXPECT_GT(bound_s, m.dt_s);
  m.set_rate(1.0 / (0.97 * bound_s));
  EXPECT_TRUE(analyze_stability(m).stable());
  constexpr double kInto_m = 0.0013;  // from 1 mm above the top
  EXPECT_GE(ring(m, m.rate_hz, 100000, kInto_m), 0.0);
  m.set_rate(1.0 / (1.5 * bound_s));
  const StabilityReport outside = analyze_stability(m);
  EXPECT_FALSE(outside.stable());
  const std::string message = instability_message(m, outside);
  EXPECT_NE(message.find("bridge_deformable.yaml:" + std::to_string(m.proxies[0].deformable.line) + ": mass 'finger/r"), std::string::npos) << message;
  EXPECT_NE(message.find("fix: lower the stiffness of"), std::string::npos) << message;
  EXPECT_EQ(ring(m, m.rate_hz, 100000, kInto_m), -1.0);
}

// --- passivity: a random walk of the device over the bridge with the deformable body ---

struct WalkCase {
  double rate_hz;
  unsigned seed;
};

class DeformableWalk : public ::testing::TestWithParam<WalkCase> {};

// no energy is created: the body starts at rest, so the work it does on the device is at
// most minus what it still holds at the end (>= 0) and what its dampers took; beyond rounding
// (forces of ~10 N over ~10^5 steps of ~0.1 mm) it never gives the device energy
TEST_P(DeformableWalk, TheDeviceGetsNoEnergy) {
  const Model m = models::bridge(GetParam().rate_hz, "CM1", enact::test::source_path("launch/scenes/bridge_deformable.yaml"));
  const std::vector<Vec3> path = models::walk_over_the_bridge(m, GetParam().seed, 10.0);
  State s = make_state(m);
  models::place_body(m, s, path.front());
  const double work_j = models::device_work_j(m, s, path);
  std::printf("work on the device: %.6g J\n", work_j);
  EXPECT_LE(work_j, 1e-9);
  EXPECT_LT(work_j, -1e-4) << "the walk pressed the body: its dampers took energy";
  EXPECT_EQ(s.faults, 0u);
}

INSTANTIATE_TEST_SUITE_P(Bridge, DeformableWalk, ::testing::Values(WalkCase{5000.0, 1}, WalkCase{5000.0, 2}, WalkCase{5000.0, 3}, WalkCase{44000.0, 1}),
                         [](const auto& p) { return std::to_string(static_cast<int>(p.param.rate_hz)) + "Hz_seed" + std::to_string(p.param.seed); });

// --- live changes ---

// a live contact stiffness past the body's step bound is refused (the device's passivity
// bound does not see it: the device is tied to the masses by their proxy links alone); the
// body's grid alone touches, so the centre's contacts do not refuse it first
TEST(LiveChange, AStiffnessPastTheStepBoundIsRefused) {
  const enact::test::TempDir dir;
  std::string text = enact::test::read_file(enact::test::source_path("launch/scenes/bridge_deformable.yaml"));
  text.replace(text.find("masses: body"), 12, "masses: grid");
  enact::test::write_file(dir.file("grid.yaml"), text);
  sim::SimParams params;
  params.scene = dir.file("grid.yaml");
  sim::Simulator simulator;
  simulator.configure(params);
  sim::ParamPlanner planner(simulator);
  sim::ParamValue stiffer;
  stiffer.number = 60000.0;
  const sim::ParamPlan refused = planner.plan("stiffness_n_per_m", stiffer, 1);
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(refused.reason.find("the deformable body would not stay stable"), std::string::npos) << refused.reason;
  EXPECT_NE(refused.reason.find("fix: lower the stiffness of"), std::string::npos) << refused.reason;
  stiffer.number = 6500.0;
  EXPECT_TRUE(planner.plan("stiffness_n_per_m", stiffer, 2).accepted);
}

// --- the scene keys ---

TEST(SceneKeys, TheShippedScene) {
  const Model m = load_scene(enact::test::source_path("launch/scenes/bridge_deformable.yaml"));
  const Proxy& p = m.proxies[0];
  EXPECT_TRUE(p.deformable.enabled());
  EXPECT_EQ(p.deformable.proxy_stiffness_n_per_m, 2000.0);
  EXPECT_EQ(p.deformable.grid_damping_n_s_per_m, 0.05);
  for (int i = 0; i < p.rows * p.cols; ++i) {
    EXPECT_EQ(m.points[p.first_body + i].kind, PointKind::dynamic);
    EXPECT_EQ(m.points[p.first_body + i].mass_kg, 0.0005);
  }
  EXPECT_EQ(m.points[p.point].kind, PointKind::kinematic);
}

std::string refusal(const std::string& deformable) {
  return enact::test::error_of_file("s.yaml",
                                    "objects: [{name: floor, type: plane, normal: [0, 0, 1]}]\n"
                                    "body:\n"
                                    "  position_m: [0, 0, 0.01]\n"
                                    "  grid: {rows: 4, cols: 4, pitch_m: 0.00245}\n"
                                    "  deformable:\n" +
                                        deformable,
                                    [](const std::string& path) { load_scene(path); });
}

TEST(SceneKeys, RefusedWithTheLineAndTheFix) {
  EXPECT_NE(refusal("    proxy_link: {stiffness_n_per_m: 2000}\n").find("s.yaml:6: a deformable body needs the mass of each grid mass\n  fix: add mass_kg"), std::string::npos);
  EXPECT_NE(refusal("    mass_kg: 0.0005\n").find("s.yaml:6: a deformable body's masses need a link to the device proxy\n  fix: add proxy_link"), std::string::npos);
  EXPECT_NE(refusal("    mass_kg: 0.0005\n    proxy_link: {damping_n_s_per_m: 0.1}\n").find("s.yaml:7: a proxy link needs a stiffness"), std::string::npos);
  EXPECT_NE(refusal("    mass_kg: 0.0005\n    proxy_link: {stiffness_n_per_m: 2000}\n    grid_link: {stiffness_n_per_m: -1}\n").find("s.yaml:8:"), std::string::npos);
  EXPECT_NE(refusal("    mass_kg: -0.0005\n    proxy_link: {stiffness_n_per_m: 2000}\n").find("s.yaml:6:"), std::string::npos);
  const std::string unknown = refusal("    mass_kg: 0.0005\n    proxy_link: {stiffness_n_per_m: 2000, damping: 1}\n");
  EXPECT_NE(unknown.find("s.yaml:7:"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("damping"), std::string::npos) << unknown;
}

}  // namespace
}  // namespace enact::physics
