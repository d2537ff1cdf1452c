// enact bench physics: speed against error of the integrators, the bridge step's cost and
// the scaling of a chain. Timing runs under Google Benchmark; errors are computed apart,
// deterministically, on scenes built in code.
#include <benchmark/benchmark.h>
#include <sched.h>
#include <sys/utsname.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/haptics/computer_model.h"
#include "core/physics/contact.h"
#include "core/physics/reference.h"
#include "core/physics/scene.h"
#include "core/sim/offline.h"
#include "core/physics/state.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/json.h"
#include "nodes/enact/sweep_report.h"
#include "nodes/enact-bench/bench_physics_mesh.h"
#include "nodes/enact-bench/bench_physics_ode.h"
#include "nodes/enact-bench/bench_physics_body.h"

namespace enact::cli {
namespace {

using physics::Integrator;
using physics::Model;
using math::Vec3;
namespace reference = physics::reference;
using reference::BounceErrors;
using reference::OscillatorErrors;
using reference::bounce_errors;
using reference::chain;
using reference::damped_error;
using reference::oscillator_50hz;
using reference::steps_in;
using reference::kIntegrators;
using reference::kRates_hz;
using reference::undamped_errors;
using mesh_rows::bumpy_field;
using mesh_rows::field_motion;
using mesh_rows::kMeshCells;
using mesh_rows::mesh_name;
using mesh_rows::on_field;

constexpr const char* kHelp = R"(usage: enact bench physics [--json FILE] [--quick] [--scene PATH]

Speed against error of the three integrators (cordis, symplectic_euler, implicit_euler)
at 1, 2, 5, 10, 20 and 44 kHz (analytic cases and the bridge scene itself), the cost of
one bridge step, and how a chain scales.
About a minute (--quick: about 15 s); progress goes to stderr, the table to stdout.

timing (Google Benchmark; medians of 5 repetitions of at least 0.2 s, wall-clock, the
repetitions of all benchmarks interleaved in a random order):
  oscillator  one step of a mass on a spring to a fixed point: ns per step and the
              real-time factor, period / ns per step (state restarted every 1 s simulated)
  bridge      one step of SCENE at 44 kHz with computer model CM1, share of the
              22.7 us period (target: 227 ns, 1 %):
                path: along the scene's scripted hand path (enact path; JSON
                      bridge_step_ns_median); the same evaluating every contact
                      pair (bridge_step_unculled_ns_median), and the culling test
                      alone (bridge_cull_test_ns_median): the pairs of the body
                      against an object are skipped while a sphere around the
                      body is apart from it
                turn: the body resting 0.1 mm into the top at the first turn, all 16 grid
                      masses touching, wobbling +-1.2 mm at 2 and 3 Hz (the worst case;
                      JSON bridge_turn_step_ns_median; target 341 ns, 1.5 %)
                both also with the full face test every step, no held faces (JSON
                bridge_step_no_hold_ns_median, bridge_turn_step_no_hold_ns_median):
                      a contact holds its face while the point stays within a
                      distance in which no other face can take over
  chain       N = 10, 100, 1000 masses in a line of springs, one end fixed (cordis):
              ns per step and per element (mass + link)
  mesh        one step of the bridge's body (CM1, 44 kHz) against a closed triangle
              mesh instead of the bridge: a height field of 1 mm bumps on a 60 mm
              square, 4 N^2 + 8 N triangles for N cells a side (96, 1020, 9996 and
              99852), the body walking over it in a Lissajous figure, 0.2 to 0.8 mm into
              the plateau (JSON mesh_rows); each row's cost against the previous one's
              and the ratio of their log(triangles): the hierarchy's search grows with
              log(triangles), plus one test per triangle within a point's depth, more
              on a finer mesh (docs/physics.md, "Meshes, height maps, spheres and capsules")

errors (deterministic, no damping added):
  oscillator  m = 0.01 kg, f0 = 50 Hz, released from A = 1 mm at rest, 1 s:
    error       max |x - A cos(w t)| / A over the run (the plotted error)
    amp err     | max |x| over the last period - A | / A
    phase       numerical minus exact phase at the last zero crossing (rad; > 0: ahead)
    freq/pred   measured frequency (zero crossings) / predicted discrete one - 1;
                predicted w_d: (2/dt) asin(w dt/2) for cordis and symplectic_euler,
                atan(w dt)/dt for implicit_euler; warping = w_d / w - 1 (JSON)
  damped      the same with zeta = 0.05: max |x - x_exact| / A
  bounce      0.01 kg dropped from 5 mm onto a plane (2000 N/m, undamped), g = 9.81:
    peak pen    first impact's peak penetration / (mg/k + sqrt((mg/k)^2 + m v^2/k)) - 1
    E drift     (E - E0) / E0 at the last step in flight within 10^6 steps (--quick
                10^5), and max |E - E0| / E0 over the steps in flight; E = m v^2/2 +
                m g (z(n) + z(n-1))/2 with v the state's velocity (x(n) - x(n-1)) / dt,
                which all three integrators keep exactly in flight; E0 after step 1
    P drift     the same with the contact passive (energy-consistent, scene key
                passive: true); its step cost against the plain contact is timed at
                1 kHz (JSON passive_cost)
  bridge      the scene along its scripted hand path under CM1 through each integrator
              at each rate, against cordis at 880 kHz (--quick 440 kHz) at the same
              instants (JSON bridge_rows): ns per step (the whole path, wall clock),
              device force error rms and max (N), share of steps whose pins differ.
              The bridge has no dynamic masses: the integrators give the same forces,
              and its force depends on the rate only through the contact damping's
              backward-difference velocity and the entry faces
  ode         (when built with ODE, libode-dev) the same path at 5 kHz in the Open Dynamics
              Engine: the grid masses as small spheres on one position-driven body, the
              bridge's boxes and the floor static, each contact a soft constraint whose
              ERP and CFM give the scene's stiffness and damping; both engines timed in
              alternating rounds (7, --quick 3: median and range of ns per step), their
              device force against the same reference (JSON ode_step_ratio: ODE's ns per
              step over ours, ode_force_error_ratio: its rms force error over ours; ode_peer)
  deformable  the same for the bridge explored by the deformable fingertip
              (launch/scenes/bridge_deformable.yaml; JSON deformable_rows): its masses are
              integrated, so the integrators and rates differ; below the body's step
              bound (enact check: about 2.8 kHz) the explicit ones diverge (faults)
  Extrema (amplitude, peak penetration) are refined by a parabola through the three
  samples around them; zero crossings are interpolated linearly.

options:
  --json FILE   also write the results as JSON (plot: scripts/plot_bench.py FILE)
  --quick       3 repetitions of at least 0.05 s, 10^5 bounce steps
  --scene PATH  bridge scene (default launch/scenes/bridge.yaml, from the current
                directory, else from the source tree above the executable)
)";

constexpr std::array kChainMasses{10, 100, 1000};
// the bounce's step timed at this rate, restarted every simulated second (a decaying
// bounce would reach denormal numbers, the plain contact gains energy)
constexpr double kBounceTiming_hz = 1000.0;

// the rate of the ODE peer's comparison: the scene's own
constexpr double kPeerRate_hz = 5000.0;
// the bridge step: its rate, the hand's depth into the top and its wobble
constexpr double kBridgeRate_hz = 44000.0;
constexpr double kBridgeTarget_ns = 227.0;      // 1 % of the period, along the path
constexpr double kBridgeTurnTarget_ns = 341.0;  // 1.5 %, at a turn
constexpr double kPressDepth_m = 1e-4;
constexpr double kPastTurn_m = 1.5e-3;     // along the second segment
constexpr double kBeforeTurn_m = 2.5e-3;   // back along the first
constexpr double kWobble_m = 1.2e-3;

struct Settings {
  int repetitions = 5;
  double min_time_s = 0.2;
  long bounce_steps = 1000000;
  double sweep_reference_hz = reference::kSweepReference_hz;
  int peer_rounds = 7;
};

// ---- the bridge: scene, hand motion ----

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

// the hand resting 0.1 mm into the top inside the first turn, where the whole grid fits,
// wobbling along both segments (2 and 3 Hz: one period of 1 s), sampled at the model's rate
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

// the built-in scripted hand path of the scene (enact path): on the top, off the edges, a
// fall and the climb back, the turns
task::Trajectory scripted_path(const std::string& scene) {
  sim::SimParams p;
  p.scene = find_file(scene);
  p.rate_hz = kBridgeRate_hz;
  p.force = true;
  sim::Simulator simulator;
  simulator.configure(p);
  return sim::scripted_path(simulator);
}

// the scripted path sampled at the bridge rate
std::vector<Vec3> scripted_motion(const task::Trajectory& tr) {
  std::vector<Vec3> motion(steps_in(tr.end_s() - tr.start_s(), kBridgeRate_hz));
  for (std::size_t n = 0; n < motion.size(); ++n) motion[n] = tr.at(tr.start_s() + static_cast<double>(n) / kBridgeRate_hz);
  return motion;
}

// the bridge at 44 kHz under CM1, the body starting 1 mm above the motion's first position
Model bridge(const std::string& scene, const std::vector<Vec3>& start) {
  Model m = physics::load_scene(find_file(scene));
  if (m.proxies.empty()) throw std::runtime_error(m.source + ": the bridge benchmark needs a body");
  m.set_rate(kBridgeRate_hz);
  haptics::apply(*haptics::preset("CM1", m.proxies[0].rows * m.proxies[0].cols), m);
  if (!start.empty()) m.points[m.proxies[0].point].position_m = start.front() + Vec3{0.0, 0.0, 1e-3};
  return m;
}

struct GridContacts {
  double mean = 0.0;      // grid masses touching, mean over the motion
  double all_share = 0.0; // share of steps with every grid mass touching
  int masses = 0;
};

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

// ---- timing ----

// the timed loop: one step per iteration. A motion drives proxy 0, its index wrapping every
// `period` steps; with `restart` the state also returns to its initial conditions then
// (by copy, no allocation), so a decaying oscillator never reaches denormal numbers. cull,
// hold: State's switches (false: every pair evaluated; the full face test every step)
void step_loop(benchmark::State& timer, const Model& m, const std::vector<Vec3>& motion, std::size_t period, bool restart,
               bool cull = true, bool hold = true) {
  physics::State initial = physics::make_state(m);
  initial.cull = cull;
  initial.hold = hold;
  physics::State s = initial;
  std::size_t n = 0;
  for (auto _ : timer) {
    if (!motion.empty()) s.proxy_position_m[0] = motion[n];
    physics::step(m, s);
    if (++n < period) continue;
    n = 0;
    if (restart) s = initial;
  }
}

// the culling test alone: each pair group's bounding sphere against its object, at the
// body positions of a motion
void cull_loop(benchmark::State& timer, const Model& m, const std::vector<Vec3>& motion) {
  const physics::State s = physics::make_state(m);
  std::size_t n = 0;
  for (auto _ : timer) {
    bool any = false;
    for (const physics::PairGroup& g : s.groups) any = any != physics::apart(m, m.objects[g.object], motion[n] + g.centre_offset_m, g.radius_m);
    benchmark::DoNotOptimize(any);
    if (++n == motion.size()) n = 0;
  }
}

// keeps the median wall-clock time of each benchmark (ns) and echoes it to stderr; nothing on stdout
class MedianReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.run_type != Run::RT_Aggregate || r.aggregate_name != "median") continue;
      if (r.error_occurred) {
        std::fprintf(stderr, "  %-34s failed: %s\n", r.run_name.function_name.c_str(), r.error_message.c_str());
        continue;
      }
      medians_ns_[r.run_name.function_name] = r.GetAdjustedRealTime();
      std::fprintf(stderr, "  %-34s %10.1f ns\n", r.run_name.function_name.c_str(), r.GetAdjustedRealTime());
    }
  }
  double median_ns(const std::string& name) const {
    const auto it = medians_ns_.find(name);
    return it == medians_ns_.end() ? NAN : it->second;
  }

 private:
  std::map<std::string, double> medians_ns_;
};

std::string oscillator_name(Integrator integrator, double rate_hz) {
  return std::string("oscillator/") + physics::to_string(integrator) + "/" + std::to_string(std::lround(rate_hz));
}

std::string chain_name(int masses) { return "chain/" + std::to_string(masses); }

std::string bounce_name(Integrator integrator, bool passive) {
  return std::string(passive ? "bounce_passive/" : "bounce/") + physics::to_string(integrator);
}

void register_benchmarks(const Model& bridge_model, const std::vector<Vec3>& motion, const Model& path_model,
                         const std::vector<Vec3>& path_motion, const std::vector<Model>& fields, const std::vector<Vec3>& field_walk) {
  for (Integrator integrator : kIntegrators) {
    for (double rate_hz : kRates_hz) {
      const Model m = oscillator_50hz(integrator, rate_hz, 0.0).model;
      const std::size_t one_second = steps_in(1.0, rate_hz);
      benchmark::RegisterBenchmark(oscillator_name(integrator, rate_hz).c_str(),
                                   [m, one_second](benchmark::State& t) { step_loop(t, m, {}, one_second, true); });
    }
    for (bool passive : {false, true}) {
      const Model m = reference::bounce(integrator, kBounceTiming_hz, passive);
      benchmark::RegisterBenchmark(bounce_name(integrator, passive).c_str(),
                                   [m](benchmark::State& t) { step_loop(t, m, {}, steps_in(1.0, kBounceTiming_hz), true); });
    }
  }
  for (bool hold : {true, false}) {
    benchmark::RegisterBenchmark(hold ? "bridge" : "bridge_no_hold", [&bridge_model, &motion, hold](benchmark::State& t) {
      step_loop(t, bridge_model, motion, motion.size(), false, true, hold);
    });
    benchmark::RegisterBenchmark(hold ? "bridge_path" : "bridge_path_no_hold", [&path_model, &path_motion, hold](benchmark::State& t) {
      step_loop(t, path_model, path_motion, path_motion.size(), false, true, hold);
    });
  }
  benchmark::RegisterBenchmark("bridge_path_unculled", [&path_model, &path_motion](benchmark::State& t) {
    step_loop(t, path_model, path_motion, path_motion.size(), false, false);
  });
  benchmark::RegisterBenchmark("bridge_cull_test", [&path_model, &path_motion](benchmark::State& t) { cull_loop(t, path_model, path_motion); });
  for (int masses : kChainMasses) {
    const Model m = chain(masses, kBridgeRate_hz);
    benchmark::RegisterBenchmark(chain_name(masses).c_str(), [m](benchmark::State& t) { step_loop(t, m, {}, SIZE_MAX, false); });
  }
  for (std::size_t k = 0; k < fields.size(); ++k) {
    benchmark::RegisterBenchmark(mesh_name(kMeshCells[k]).c_str(), [&fields, &field_walk, k](benchmark::State& t) {
      step_loop(t, fields[k], field_walk, field_walk.size(), false);
    });
  }
}

// Google Benchmark with synthetic flags: repetitions, aggregates only, minimum time each, interleaved
void run_benchmarks(const Settings& settings, MedianReporter& reporter) {
  char min_time[32];
  std::snprintf(min_time, sizeof min_time, "%g", settings.min_time_s);
  // the repetitions of all benchmarks interleaved in a random order: arms compared side by side
  // share the machine's drifts
  std::vector<std::string> flags{"enact", "--benchmark_repetitions=" + std::to_string(settings.repetitions),
                                 "--benchmark_report_aggregates_only=true", std::string("--benchmark_min_time=") + min_time,
                                 "--benchmark_enable_random_interleaving=true"};
  std::vector<char*> argv;
  for (std::string& f : flags) argv.push_back(f.data());
  int argc = static_cast<int>(argv.size());
  benchmark::Initialize(&argc, argv.data());
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::ClearRegisteredBenchmarks();
  benchmark::Shutdown();
}

// ---- results ----

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
  int triangles = 0;
  double ns_per_step = 0.0;
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
  std::vector<MeshRow> mesh;
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
Machine machine() {
  Machine m;
  utsname u{};
  if (uname(&u) == 0) m.arch = u.machine;
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    const auto colon = line.find(':');
    if (line.rfind("model name", 0) == 0 && colon != std::string::npos) {
      m.cpu = line.substr(line.find_first_not_of(" \t", colon + 1));
      break;
    }
  }
  cpu_set_t set;
  CPU_ZERO(&set);
  m.cores = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 0;
  return m;
}

// observed order of the global error: slope of log(error) against log(rate), least squares
double convergence_order(const std::vector<Row>& rows, Integrator integrator) {
  double n = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (const Row& r : rows) {
    if (r.integrator != integrator) continue;
    const double lx = std::log(r.rate_hz), ly = std::log(r.oscillator.global);
    n += 1.0;
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return -(n * sxy - sx * sy) / (n * sxx - sx * sx);
}

void print_table(const Results& r) {
  std::printf("%-16s %6s %9s %9s %9s %9s %9s %10s %9s %9s %10s %9s %10s\n", "integrator", "kHz", "ns/step", "RT factor", "error",
              "amp err", "phase rad", "freq/pred", "damped", "peak pen", "E drift", "E max", "P drift");
  for (const Row& w : r.rows) {
    std::printf("%-16s %6.0f %9.1f %9.0f %9.2e %9.2e %9.2e %10.2e %9.2e %9.2e %10.2e %9.2e %10.2e\n", physics::to_string(w.integrator),
                w.rate_hz / 1e3, w.ns_per_step, w.realtime_factor(), w.oscillator.global, w.oscillator.amplitude,
                w.oscillator.phase_rad, w.oscillator.freq_vs_predicted, w.damped_error, w.bounce.peak_penetration,
                w.bounce.energy_drift, w.bounce.energy_drift_max, w.passive_bounce.energy_drift);
  }
  for (const PassiveCost& c : r.passive_cost) {
    std::printf("passive contact  %-16s bounce step %.1f ns plain, %.1f ns passive (x%.2f)\n", physics::to_string(c.integrator), c.plain_ns,
                c.passive_ns, c.ratio());
  }
  std::printf("\nobserved order of the global error (1 to 44 kHz):");
  for (Integrator integrator : kIntegrators) std::printf(" %s %.2f", physics::to_string(integrator), convergence_order(r.rows, integrator));
  const GridContacts& c = r.bridge_contacts;
  std::printf("\nbridge step  along the scripted hand path: %.1f ns median at 44 kHz, %.2f %% of the 22.7 us period (target %.0f ns: %s)\n",
              r.bridge_path_ns, 100.0 * r.bridge_path_ns * 1e-9 * kBridgeRate_hz, kBridgeTarget_ns,
              r.bridge_path_ns <= kBridgeTarget_ns ? "met" : "NOT met");
  std::printf("bridge step  the same evaluating every pair: %.1f ns; the culling test alone: %.1f ns per step\n", r.bridge_path_unculled_ns,
              r.bridge_cull_test_ns);
  std::printf("bridge step  at a turn (worst case): %.1f ns median, %.2f %% of the period (target %.0f ns: %s); "
              "%.1f of %d grid masses touching on average, all on %.0f %% of steps\n",
              r.bridge_ns, 100.0 * r.bridge_share(), kBridgeTurnTarget_ns, r.bridge_ns <= kBridgeTurnTarget_ns ? "met" : "NOT met", c.mean,
              c.masses, 100.0 * c.all_share);
  std::printf("bridge step  the full face test every step (no held faces): %.1f ns along the path (x%.2f), %.1f ns at a turn (x%.2f)\n",
              r.bridge_path_no_hold_ns, r.bridge_path_no_hold_ns / r.bridge_path_ns, r.bridge_no_hold_ns, r.bridge_no_hold_ns / r.bridge_ns);
  print_sweep(r.bridge_rows, "bridge along its scripted path (CM1), device force against the reference");
  if (r.ode) ode_peer::print(*r.ode);
  print_deformable_rows(r.deformable);
  for (const ChainRow& w : r.chain) {
    std::printf("chain %-6d %.1f ns per step, %.2f ns per element (mass + link)\n", w.masses, w.ns_per_step, w.ns_per_element());
  }
  for (std::size_t k = 0; k < r.mesh.size(); ++k) {
    const MeshRow& w = r.mesh[k];
    std::printf("mesh %-7d %.1f ns per step", w.triangles, w.ns_per_step);
    if (k > 0) {
      const MeshRow& before = r.mesh[k - 1];
      std::printf(" (x%.2f the %d-triangle row's; log(triangles) x%.2f)", w.ns_per_step / before.ns_per_step, before.triangles,
                  std::log(static_cast<double>(w.triangles)) / std::log(static_cast<double>(before.triangles)));
    }
    std::printf("\n");
  }
  std::printf("machine      %s, %s, %d cores; times are wall-clock medians of %d repetitions (min %g s each)\n",
              r.machine.arch.c_str(), r.machine.cpu.c_str(), r.machine.cores, r.settings.repetitions, r.settings.min_time_s);
}

void write_json(const Results& r, const std::string& path) {
  Json j;
  j.begin_object().key("machine").begin_object().field("arch", r.machine.arch).field("cpu", r.machine.cpu);
  j.field("cores", r.machine.cores).end_object();
  j.field("repetitions", r.settings.repetitions).field("min_time_s", r.settings.min_time_s);
  j.field("bounce_steps", static_cast<long long>(r.settings.bounce_steps));
  j.field("bridge_step_ns_median", r.bridge_path_ns).field("bridge_share_of_44khz_period", r.bridge_path_ns * 1e-9 * kBridgeRate_hz);
  j.field("bridge_step_unculled_ns_median", r.bridge_path_unculled_ns).field("bridge_cull_test_ns_median", r.bridge_cull_test_ns);
  j.field("bridge_turn_step_ns_median", r.bridge_ns).field("bridge_turn_share_of_44khz_period", r.bridge_share());
  j.field("bridge_step_no_hold_ns_median", r.bridge_path_no_hold_ns).field("bridge_turn_step_no_hold_ns_median", r.bridge_no_hold_ns);
  j.field("bridge_grid_contacts_mean", r.bridge_contacts.mean).field("bridge_all_grid_contacts_share", r.bridge_contacts.all_share);
  if (r.ode) ode_peer::json(j, *r.ode);
  j.key("chain").begin_array();
  for (const ChainRow& w : r.chain) {
    j.begin_object().field("masses", w.masses).field("ns_per_step", w.ns_per_step).field("ns_per_element", w.ns_per_element()).end_object();
  }
  j.end_array().key("mesh_rows").begin_array();
  for (std::size_t k = 0; k < r.mesh.size(); ++k) {
    const MeshRow& w = r.mesh[k];
    j.begin_object().field("triangles", w.triangles).field("ns_per_step", w.ns_per_step);
    if (k > 0) j.field("ratio_to_previous", w.ns_per_step / r.mesh[k - 1].ns_per_step);
    j.end_object();
  }
  j.end_array().key("rows").begin_array();
  for (const Row& w : r.rows) {
    j.begin_object().field("integrator", physics::to_string(w.integrator)).field("rate_hz", w.rate_hz);
    j.field("ns_per_step", w.ns_per_step).field("realtime_factor", w.realtime_factor()).field("error", w.oscillator.global);
    j.field("amplitude_error", w.oscillator.amplitude).field("phase_error_rad", w.oscillator.phase_rad);
    j.field("freq_error_vs_predicted", w.oscillator.freq_vs_predicted).field("freq_warping", w.oscillator.freq_warping);
    j.field("damped_error", w.damped_error).field("bounce_peak_penetration_error", w.bounce.peak_penetration);
    j.field("bounce_energy_drift", w.bounce.energy_drift).field("bounce_energy_drift_max", w.bounce.energy_drift_max);
    j.field("passive_bounce_energy_drift", w.passive_bounce.energy_drift);
    j.field("passive_bounce_energy_drift_max", w.passive_bounce.energy_drift_max).end_object();
  }
  j.end_array().key("bridge_rows");
  sweep_json(j, r.bridge_rows);
  deformable_rows_json(j, r.deformable);
  j.key("passive_cost").begin_array();
  for (const PassiveCost& c : r.passive_cost) {
    j.begin_object().field("integrator", physics::to_string(c.integrator)).field("rate_hz", kBounceTiming_hz);
    j.field("bounce_ns_per_step", c.plain_ns).field("passive_bounce_ns_per_step", c.passive_ns).field("ratio", c.ratio()).end_object();
  }
  j.end_array().end_object();
  std::ofstream out(path);
  out << j.str() << "\n";
  if (!out) throw std::runtime_error("cannot write " + path);
}

// the deterministic error part of every row
std::vector<Row> error_rows(const Settings& settings) {
  std::vector<Row> rows;
  for (Integrator integrator : kIntegrators) {
    std::fprintf(stderr, "enact bench: errors of %s\n", physics::to_string(integrator));
    for (double rate_hz : kRates_hz) {
      rows.push_back({.integrator = integrator,
                      .rate_hz = rate_hz,
                      .oscillator = undamped_errors(integrator, rate_hz),
                      .damped_error = damped_error(integrator, rate_hz),
                      .bounce = bounce_errors(integrator, rate_hz, settings.bounce_steps, false),
                      .passive_bounce = bounce_errors(integrator, rate_hz, settings.bounce_steps, true)});
    }
  }
  return rows;
}

Results run_physics(const Settings& settings, const std::string& scene) {
  Results r;
  r.machine = machine();
  r.settings = settings;
  r.rows = error_rows(settings);
  // the bridge: motion at its rate, contacts counted outside the timing
  const std::vector<Vec3> motion = bridge_motion(bridge(scene, {}));
  const Model bridge_model = bridge(scene, motion);
  r.bridge_contacts = grid_contacts(bridge_model, motion);
  const task::Trajectory path = scripted_path(scene);
  const std::vector<Vec3> path_motion = scripted_motion(path);
  const Model path_model = bridge(scene, path_motion);
  std::fprintf(stderr, "enact bench: the bridge along its scripted path, 3 integrators x 6 rates against %.0f kHz\n", settings.sweep_reference_hz / 1e3);
  const haptics::ComputerModel cm1 = *haptics::preset("CM1", path_model.proxies[0].rows * path_model.proxies[0].cols);
  const reference::HandPath hand = [&path](double t) { return path.at(path.start_s() + t); };
  r.bridge_rows = reference::rate_sweep(path_model, [&cm1](const Model& m, const physics::State& s) { return haptics::pins(cm1, m, s); }, hand,
                                        path.end_s() - path.start_s(), settings.sweep_reference_hz);
#if ENACT_BENCH_ODE
  std::fprintf(stderr, "enact bench: the bridge in ODE beside ours at %.0f kHz, against %.0f kHz\n", kPeerRate_hz / 1e3,
               settings.sweep_reference_hz / 1e3);
  r.ode = ode_peer::compare(path_model, cm1, hand, path.end_s() - path.start_s(), kPeerRate_hz, settings.sweep_reference_hz, settings.peer_rounds);
#endif
  r.deformable = deformable_rows("launch/scenes/bridge_deformable.yaml", settings.sweep_reference_hz);
  std::fprintf(stderr, "enact bench: timing, %zu benchmarks x %d repetitions (medians)\n",
               kIntegrators.size() * (kRates_hz.size() + 2) + 6 + kChainMasses.size() + kMeshCells.size(), settings.repetitions);
  std::fprintf(stderr, "enact bench: building the mesh rows' height fields\n");
  std::vector<Model> fields;
  for (int cells : kMeshCells) fields.push_back(on_field(bridge_model, bumpy_field(cells)));
  const std::vector<Vec3> field_walk = field_motion(kBridgeRate_hz);
  MedianReporter reporter;
  register_benchmarks(bridge_model, motion, path_model, path_motion, fields, field_walk);
  run_benchmarks(settings, reporter);
  for (Row& w : r.rows) w.ns_per_step = reporter.median_ns(oscillator_name(w.integrator, w.rate_hz));
  for (Integrator integrator : kIntegrators) {
    r.passive_cost.push_back({integrator, reporter.median_ns(bounce_name(integrator, false)), reporter.median_ns(bounce_name(integrator, true))});
  }
  r.bridge_ns = reporter.median_ns("bridge");
  r.bridge_path_ns = reporter.median_ns("bridge_path");
  r.bridge_path_unculled_ns = reporter.median_ns("bridge_path_unculled");
  r.bridge_path_no_hold_ns = reporter.median_ns("bridge_path_no_hold");
  r.bridge_no_hold_ns = reporter.median_ns("bridge_no_hold");
  r.bridge_cull_test_ns = reporter.median_ns("bridge_cull_test");
  for (int masses : kChainMasses) r.chain.push_back({.masses = masses, .ns_per_step = reporter.median_ns(chain_name(masses))});
  for (std::size_t k = 0; k < fields.size(); ++k) {
    r.mesh.push_back({static_cast<int>(fields[k].meshes[0].triangles.size()), reporter.median_ns(mesh_name(kMeshCells[k]))});
  }
  return r;
}

}  // namespace

int bench(int argc, char** argv) {
  if (argc > 2 && std::string(argv[2]) == "loop") return bench_loop(argc, argv);
  if (argc > 2 && std::string(argv[2]) == "record") return bench_record(argc, argv);
  const Args a = parse(argc, argv, 2, {"json", "scene"}, {"quick"});
  if (a.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1 || a.positional[0] != "physics") {
    throw UsageError(a.positional.empty() ? "give a benchmark: physics, loop or record" : "unknown benchmark '" + a.positional[0] + "' (physics, loop, record)");
  }
  const Settings settings = a.flag("quick") ? Settings{.repetitions = 3, .min_time_s = 0.05, .bounce_steps = 100000,
                                                        .sweep_reference_hz = reference::kSweepQuickReference_hz, .peer_rounds = 3}
                                            : Settings{};
  const Results r = run_physics(settings, a.get("scene", "launch/scenes/bridge.yaml"));
  print_table(r);
  if (a.has("json")) write_json(r, a.get("json"));
  return 0;
}

}  // namespace enact::cli
