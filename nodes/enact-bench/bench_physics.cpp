// enact bench physics: speed against error of the integrators, the bridge step's cost and
// the scaling of a chain. Timing runs under Google Benchmark; errors are computed apart,
// deterministically, on scenes built in code.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "core/haptics/computer_model.h"
#include "core/physics/contact.h"
#include "core/physics/reference.h"
#include "core/physics/state.h"
#include "nodes/enact/commands.h"
#include "nodes/enact-bench/bench_physics.h"
#include "nodes/enact-bench/bench_physics_body.h"
#include "nodes/enact-bench/bench_physics_bridge.h"
#include "nodes/enact-bench/bench_physics_mesh.h"
#include "nodes/enact-bench/bench_physics_ode.h"

namespace enact::cli {
namespace {

using physics::Model;
using math::Vec3;
using namespace physics_bench;  // Settings, Results, Integrator, reference, kBridgeRate_hz
using reference::bounce_errors;
using reference::chain;
using reference::damped_error;
using reference::oscillator_50hz;
using reference::steps_in;
using reference::kIntegrators;
using reference::kRates_hz;
using reference::undamped_errors;
using bridge_rows::bridge;
using bridge_rows::bridge_motion;
using bridge_rows::grid_contacts;
using bridge_rows::scripted_motion;
using bridge_rows::scripted_path;
using mesh_rows::field_mesh;
using mesh_rows::field_motion;
using mesh_rows::field_specs;
using mesh_rows::FieldSpec;
using mesh_rows::mesh_name;
using mesh_rows::on_field;

constexpr const char* kBenchPhysicsHelp = R"(usage: enact bench physics [--json FILE] [--quick] [--scene PATH] [--only mesh]

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
              mesh instead of the bridge: a height field of 1 mm bumps on a 5 mm
              plateau, 4 N^2 + 8 N triangles for N cells a side, the body walking over
              it in a Lissajous figure over 40 x 40 mm, 0.2 to 0.8 mm into the plateau.
              Two sets of rows, each row's cost against the previous one's in its set
              beside the ratio of their log(triangles):
                refined:    the same 60 mm square in N = 4, 15, 49, 157 cells (96, 1020,
                            9996, 99852 triangles): the triangles near the body shrink
                            (15 to 0.38 mm), so a point leaves its held triangle more
                            often and a search tests more near-equidistant triangles
                            (JSON mesh_rows)
                fixed_cell: 15 mm cells, the square grown to N = 4, 16, 50, 158 cells
                            (96, 1152, 10400, 101120 triangles, up to 2.4 m a side):
                            the same triangles near the body, only the hierarchy
                            deepens (JSON mesh_fixed_cell_rows)
              and, counted over one pass of the walk outside the timing, per contact pair
              and step: searches of the hierarchy, steps that took the nearest of the last
              search's ring (the triangles sharing a vertex with its nearest), the rest
              held (the held triangle alone); per search the boxes and triangles tested,
              for the nearest and for the nearest beyond its ring; the hierarchy's depth
              (docs/physics.md, "Meshes, height maps, spheres and capsules")

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
  --json FILE   also write the results as JSON (plot: scripts/plot_bench.py FILE, enact share)
  --quick       3 repetitions of at least 0.05 s, 10^5 bounce steps
  --scene PATH  bridge scene (default launch/scenes/bridge.yaml, from the current
                directory, else from the source tree above the executable)
  --only mesh   the mesh rows alone (timing and counts; about 30 s)
)";

constexpr std::array kChainMasses{10, 100, 1000};
// the rate of the ODE peer's comparison: the scene's own
constexpr double kPeerRate_hz = 5000.0;

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
                         const std::vector<Vec3>& path_motion) {
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
}

void register_mesh_benchmarks(const std::vector<FieldSpec>& specs, const std::vector<Model>& fields, const std::vector<Vec3>& walk) {
  for (std::size_t k = 0; k < fields.size(); ++k) {
    benchmark::RegisterBenchmark(mesh_name(specs[k]).c_str(), [&fields, &walk, k](benchmark::State& t) {
      step_loop(t, fields[k], walk, walk.size(), false);
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

// the deterministic rows: errors, the bridge's rate sweep, the ODE peer, the deformable fingertip
void sweep_rows(const Settings& settings, const Model& bridge_model, const std::vector<Vec3>& motion,
                const task::Trajectory& path, const Model& path_model, Results& r) {
  r.rows = error_rows(settings);
  r.bridge_contacts = grid_contacts(bridge_model, motion);
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
}

// the timed rows' medians, but the mesh rows'
void collect_medians(const MedianReporter& reporter, Results& r) {
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
}

Results run_physics(const Settings& settings, const std::string& scene) {
  Results r;
  r.machine = machine();
  r.settings = settings;
  // the bridge: motion at its rate, contacts counted outside the timing
  const std::vector<Vec3> motion = bridge_motion(bridge(scene, {}));
  const Model bridge_model = bridge(scene, motion);
  const task::Trajectory path = scripted_path(scene);
  const std::vector<Vec3> path_motion = scripted_motion(path);
  const Model path_model = bridge(scene, path_motion);
  if (!settings.mesh_only) sweep_rows(settings, bridge_model, motion, path, path_model, r);
  std::fprintf(stderr, "enact bench: building the mesh rows' height fields\n");
  const std::vector<FieldSpec> specs = field_specs();
  std::vector<Model> fields;
  for (const FieldSpec& spec : specs) fields.push_back(on_field(bridge_model, field_mesh(spec)));
  const std::vector<Vec3> field_walk = field_motion(kBridgeRate_hz);
  const std::size_t others = settings.mesh_only ? 0 : kIntegrators.size() * (kRates_hz.size() + 2) + 6 + kChainMasses.size();
  std::fprintf(stderr, "enact bench: timing, %zu benchmarks x %d repetitions (medians)\n", others + specs.size(), settings.repetitions);
  MedianReporter reporter;
  if (!settings.mesh_only) register_benchmarks(bridge_model, motion, path_model, path_motion);
  register_mesh_benchmarks(specs, fields, field_walk);
  run_benchmarks(settings, reporter);
  if (!settings.mesh_only) collect_medians(reporter, r);
  std::fprintf(stderr, "enact bench: counting the mesh rows' searches over one pass of the walk\n");
  for (std::size_t k = 0; k < fields.size(); ++k) {
    r.mesh.push_back({specs[k], static_cast<int>(fields[k].meshes[0].triangles.size()), reporter.median_ns(mesh_name(specs[k])),
                      mesh_rows::count_lookups(fields[k], field_walk)});
  }
  return r;
}

}  // namespace

int bench(int argc, char** argv) {
  if (argc > 2 && std::string(argv[2]) == "loop") return bench_loop(argc, argv);
  if (argc > 2 && std::string(argv[2]) == "record") return bench_record(argc, argv);
  const Args a = parse(argc, argv, 2, {"json", "scene", "only"}, {"quick"});
  if (a.flag("help")) {
    std::fputs(kBenchPhysicsHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1 || a.positional[0] != "physics") {
    throw UsageError(a.positional.empty() ? "give a benchmark: physics, loop or record" : "unknown benchmark '" + a.positional[0] + "' (physics, loop, record)");
  }
  if (a.has("only") && a.get("only") != "mesh") throw UsageError("--only takes mesh (the mesh rows alone), not '" + a.get("only") + "'");
  Settings settings = a.flag("quick") ? Settings{.repetitions = 3, .min_time_s = 0.05, .bounce_steps = 100000,
                                                  .sweep_reference_hz = reference::kSweepQuickReference_hz, .peer_rounds = 3}
                                      : Settings{};
  settings.mesh_only = a.has("only");
  const Results r = run_physics(settings, a.get("scene", "launch/scenes/bridge.yaml"));
  print_table(r);
  if (a.has("json")) write_json(r, a.get("json"));
  return 0;
}

}  // namespace enact::cli
