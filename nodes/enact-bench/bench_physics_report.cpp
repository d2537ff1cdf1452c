// enact bench physics: the machine, the table and the JSON (bench_physics.h)
#include "nodes/enact-bench/bench_physics.h"

#include <sched.h>
#include <sys/utsname.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "nodes/enact/json.h"
#include "nodes/enact/sweep_report.h"

namespace enact::cli::physics_bench {

using physics::reference::kIntegrators;

namespace {

// the bridge step's targets: 1 % of the 44 kHz period along the path, 1.5 % at a turn
constexpr double kBridgeTarget_ns = 227.0;
constexpr double kBridgeTurnTarget_ns = 341.0;

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

// the mesh rows of one set, each against the previous one of its set
void print_mesh_rows(const std::vector<MeshRow>& rows, mesh_rows::FieldSet set) {
  const MeshRow* before = nullptr;
  for (const MeshRow& w : rows) {
    if (w.field.set != set) continue;
    const mesh_rows::LookupCounts& c = w.counts;
    std::printf("mesh %-10s %6d triangles, cells %5.2f mm: %7.1f ns per step", mesh_rows::to_string(set), w.triangles, w.field.cell_m * 1e3,
                w.ns_per_step);
    if (before != nullptr) {
      std::printf(" (x%.2f the %d-triangle row's; log(triangles) x%.2f)", w.ns_per_step / before->ns_per_step, before->triangles,
                  std::log(static_cast<double>(w.triangles)) / std::log(static_cast<double>(before->triangles)));
    }
    std::printf("\n     %-10s a pair step: %.4f searches, %.4f from the ring, %.1f %% held (%.0f %% in contact); a search: %.1f boxes and %.1f "
                "triangles, + %.1f and %.1f beyond the ring; depth %d\n",
                "", c.per_pair_step(c.searches), c.per_pair_step(c.ring_steps), 100.0 * c.held_share(), 100.0 * c.per_pair_step(c.in_contact),
                c.per_search(c.nearest.nodes), c.per_search(c.nearest.triangles), c.per_search(c.beyond.nodes), c.per_search(c.beyond.triangles),
                c.depth);
    before = &w;
  }
}

void write_file(const std::string& path, const Json& j) {
  std::ofstream out(path);
  out << j.str() << "\n";
  if (!out) throw std::runtime_error("cannot write " + path);
}

void print_machine(const Results& r) {
  std::printf("machine      %s, %s, %d cores; times are wall-clock medians of %d repetitions (min %g s each)\n",
              r.machine.arch.c_str(), r.machine.cpu.c_str(), r.machine.cores, r.settings.repetitions, r.settings.min_time_s);
}

void mesh_rows_json(Json& j, const std::vector<MeshRow>& rows, mesh_rows::FieldSet set) {
  j.begin_array();
  const MeshRow* before = nullptr;
  for (const MeshRow& w : rows) {
    if (w.field.set != set) continue;
    const mesh_rows::LookupCounts& c = w.counts;
    j.begin_object().field("triangles", w.triangles).field("cell_m", w.field.cell_m).field("ns_per_step", w.ns_per_step);
    if (before != nullptr) {
      j.field("ratio_to_previous", w.ns_per_step / before->ns_per_step);
      j.field("log_ratio_to_previous", std::log(static_cast<double>(w.triangles)) / std::log(static_cast<double>(before->triangles)));
    }
    j.field("searches_per_pair_step", c.per_pair_step(c.searches)).field("ring_steps_per_pair_step", c.per_pair_step(c.ring_steps));
    j.field("held_share", c.held_share()).field("depth", c.depth);
    j.field("nodes_per_search", c.per_search(c.nearest.nodes)).field("triangles_per_search", c.per_search(c.nearest.triangles));
    j.field("beyond_nodes_per_search", c.per_search(c.beyond.nodes)).field("beyond_triangles_per_search", c.per_search(c.beyond.triangles));
    j.end_object();
    before = &w;
  }
  j.end_array();
}

}  // namespace

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

void print_table(const Results& r) {
  if (r.settings.mesh_only) {
    print_mesh_rows(r.mesh, mesh_rows::FieldSet::refined);
    print_mesh_rows(r.mesh, mesh_rows::FieldSet::fixed_cell);
    print_machine(r);
    return;
  }
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
  print_mesh_rows(r.mesh, mesh_rows::FieldSet::refined);
  print_mesh_rows(r.mesh, mesh_rows::FieldSet::fixed_cell);
  print_machine(r);
}

void write_json(const Results& r, const std::string& path) {
  Json j;
  j.begin_object().key("machine").begin_object().field("arch", r.machine.arch).field("cpu", r.machine.cpu);
  j.field("cores", r.machine.cores).end_object();
  j.field("repetitions", r.settings.repetitions).field("min_time_s", r.settings.min_time_s);
  j.field("bounce_steps", static_cast<long long>(r.settings.bounce_steps));
  j.key("mesh_rows");
  mesh_rows_json(j, r.mesh, mesh_rows::FieldSet::refined);
  j.key("mesh_fixed_cell_rows");
  mesh_rows_json(j, r.mesh, mesh_rows::FieldSet::fixed_cell);
  if (r.settings.mesh_only) {
    j.end_object();
    write_file(path, j);
    return;
  }
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
  write_file(path, j);
}

}  // namespace enact::cli::physics_bench
