#pragma once
// enact bench physics: what one run measured (bench_physics.cpp runs it), and its table and
// JSON (bench_physics_report.cpp).
#include <optional>
#include <string>
#include <vector>

#include "core/physics/model.h"
#include "core/physics/reference.h"
#include "nodes/enact-bench/bench_physics_body.h"
#include "nodes/enact-bench/bench_physics_bridge.h"
#include "nodes/enact-bench/bench_physics_mesh.h"
#include "nodes/enact-bench/bench_physics_ode.h"

namespace enact::cli::physics_bench {

using physics::Integrator;
namespace reference = physics::reference;
using physics::reference::BounceErrors;
using physics::reference::OscillatorErrors;
using bridge_rows::GridContacts;
using bridge_rows::kBridgeRate_hz;

// the bounce's step timed at this rate, restarted every simulated second (a decaying
// bounce would reach denormal numbers, the plain contact gains energy)
inline constexpr double kBounceTiming_hz = 1000.0;

struct Settings {
  int repetitions = 5;
  double min_time_s = 0.2;
  long bounce_steps = 1000000;
  double sweep_reference_hz = physics::reference::kSweepReference_hz;
  int peer_rounds = 7;
  bool mesh_only = false;  // --only mesh: the mesh rows alone
};

struct Row {
  Integrator integrator = Integrator::cordis;
  double rate_hz = 0.0;
  double ns_per_step = 0.0;
  OscillatorErrors oscillator;
  double damped_error = 0.0;
  BounceErrors bounce;
  BounceErrors passive_bounce;
  double realtime_factor() const { return 1e9 / rate_hz / ns_per_step; }
};

struct MeshRow {
  mesh_rows::FieldSpec field;
  int triangles = 0;
  double ns_per_step = 0.0;
  mesh_rows::LookupCounts counts;
};

struct ChainRow {
  int masses = 0;
  double ns_per_step = 0.0;
  double ns_per_element() const { return ns_per_step / (2.0 * masses); }  // masses + links
};

// the step cost of the bounce with the plain and the passive contact
struct PassiveCost {
  Integrator integrator = Integrator::cordis;
  double plain_ns = 0.0;
  double passive_ns = 0.0;
  double ratio() const { return passive_ns / plain_ns; }
};

struct Machine {
  std::string arch;
  std::string cpu = "unknown";
  int cores = 0;
};

struct Results {
  Machine machine;
  Settings settings;
  std::vector<Row> rows;
  std::vector<ChainRow> chain;
  std::vector<MeshRow> mesh;  // the refined set, then the fixed-cell set
  std::vector<PassiveCost> passive_cost;
  double bridge_ns = 0.0;       // at a turn, all 16 grid masses on the top (the worst case)
  std::vector<reference::SweepRow> bridge_rows;
  double bridge_path_ns = 0.0;  // along the scripted hand path
  double bridge_path_unculled_ns = 0.0;  // the same evaluating every pair
  double bridge_path_no_hold_ns = 0.0;   // the same with the full face test every step
  double bridge_no_hold_ns = 0.0;        // at a turn, the full face test every step
  double bridge_cull_test_ns = 0.0;      // the culling test alone, per step
  GridContacts bridge_contacts;
  std::optional<ode_peer::Comparison> ode;  // when built with ODE
  BodyRows deformable;  // the deformable fingertip's sweep (bench_physics_body.cpp)
  double bridge_share() const { return bridge_ns * 1e-9 * kBridgeRate_hz; }
};

// `uname -m`, the CPU model from /proc/cpuinfo, `nproc`
Machine machine();
// the table on stdout
void print_table(const Results& r);
// every figure as JSON to `path`
void write_json(const Results& r, const std::string& path);

}  // namespace enact::cli::physics_bench
