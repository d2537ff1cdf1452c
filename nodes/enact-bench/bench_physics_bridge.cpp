// enact bench physics: the bridge's inputs (bench_physics_bridge.h)
#include "nodes/enact-bench/bench_physics_bridge.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>

#include "core/haptics/computer_model.h"
#include "core/physics/contact.h"
#include "core/physics/reference.h"
#include "core/physics/scene.h"
#include "core/physics/state.h"
#include "core/sim/offline.h"
#include "nodes/enact/commands.h"

namespace enact::cli::bridge_rows {

using math::Vec3;
using physics::Model;
using physics::reference::steps_in;

namespace {

// the hand's rest at the first turn: how deep into the top, and where
constexpr double kPressDepth_m = 1e-4;
constexpr double kPastTurn_m = 1.5e-3;     // along the second segment
constexpr double kBeforeTurn_m = 2.5e-3;   // back along the first
constexpr double kWobble_m = 1.2e-3;

Vec3 unit(const Vec3& v) { return v * (1.0 / math::norm(v)); }

// the path object the body explores: the task surface, else the first path
const physics::Object& bridge_path(const Model& m) {
  const int task = m.find_object(m.task_surface);
  if (task >= 0 && m.objects[task].is_path && m.objects[task].path.centerline_m.size() >= 3) return m.objects[task];
  for (const auto& o : m.objects) {
    if (o.is_path && o.path.centerline_m.size() >= 3) return o;
  }
  throw std::runtime_error(m.source + ": the bridge benchmark needs a path object with a turn (3 points or more)");
}

}  // namespace

std::vector<Vec3> bridge_motion(const Model& m) {
  const physics::PathGeometry& g = bridge_path(m).path;
  const Vec3 along_first = unit(g.centerline_m[1] - g.centerline_m[0]);
  const Vec3 along_second = unit(g.centerline_m[2] - g.centerline_m[1]);
  Vec3 centre = g.centerline_m[1] + along_second * kPastTurn_m - along_first * kBeforeTurn_m;
  centre.z = g.top_z_m - kPressDepth_m;
  std::vector<Vec3> motion(steps_in(1.0, m.rate_hz));
  for (std::size_t n = 0; n < motion.size(); ++n) {
    const double phase = 2.0 * std::numbers::pi * static_cast<double>(n) * m.dt_s;
    motion[n] = centre + along_first * (kWobble_m * std::sin(2.0 * phase)) + along_second * (kWobble_m * std::sin(3.0 * phase));
  }
  return motion;
}

task::Trajectory scripted_path(const std::string& scene) {
  sim::SimParams p;
  p.scene = find_file(scene);
  p.rate_hz = kBridgeRate_hz;
  p.force = true;
  sim::Simulator simulator;
  simulator.configure(p);
  return sim::scripted_path(simulator);
}

std::vector<Vec3> scripted_motion(const task::Trajectory& tr) {
  std::vector<Vec3> motion(steps_in(tr.end_s() - tr.start_s(), kBridgeRate_hz));
  for (std::size_t n = 0; n < motion.size(); ++n) motion[n] = tr.at(tr.start_s() + static_cast<double>(n) / kBridgeRate_hz);
  return motion;
}

Model bridge(const std::string& scene, const std::vector<Vec3>& start) {
  Model m = physics::load_scene(find_file(scene));
  if (m.proxies.empty()) throw std::runtime_error(m.source + ": the bridge benchmark needs a body");
  m.set_rate(kBridgeRate_hz);
  haptics::apply(*haptics::preset("CM1", m.proxies[0].rows * m.proxies[0].cols), m);
  if (!start.empty()) m.points[m.proxies[0].point].position_m = start.front() + Vec3{0.0, 0.0, 1e-3};
  return m;
}

GridContacts grid_contacts(const Model& m, const std::vector<Vec3>& motion) {
  physics::State s = physics::make_state(m);
  const physics::Proxy& body = m.proxies[0];
  GridContacts c{.masses = body.rows * body.cols};
  for (const Vec3& p : motion) {
    s.proxy_position_m[0] = p;
    physics::step(m, s);
    const auto first = s.in_contact.begin() + body.first_body;
    const auto touching = std::count(first, first + c.masses, std::uint8_t{1});
    c.mean += static_cast<double>(touching);
    c.all_share += touching == c.masses ? 1.0 : 0.0;
  }
  c.mean /= static_cast<double>(motion.size());
  c.all_share /= static_cast<double>(motion.size());
  return c;
}

}  // namespace enact::cli::bridge_rows
