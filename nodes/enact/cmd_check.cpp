// enact check SCENE: load, validate, stability table; --json adds the geometry.
#include <cmath>
#include <cstdio>
#include <iostream>

#include "core/config/share.h"
#include "core/config/yaml.h"
#include "core/haptics/computer_model.h"
#include "core/sim/params.h"
#include "core/devices/device_profile.h"
#include "core/physics/scene.h"
#include "core/physics/stability.h"
#include "core/sim/offline.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/json.h"
#include "nodes/enact/sweep_report.h"

namespace enact::cli {
namespace {

namespace reference = physics::reference;

constexpr const char* kCheckHelp = R"(usage: enact check SCENE [--rate HZ] [--model CM] [--device NAME] [--json] [--rate-sweep]

Load and validate a scene file, then print its stability table: for each mass the
integrator's discrete stability bound at the rate (K + 2Z < 4M for the explicit
schemes), and for each body the device passivity bound (b > K T/2 + B).
Exit status: 0 stable, 1 unstable or invalid (the message names file:line and the fix).

options:
  --rate HZ      loop rate (default: the scene's rate_hz)
  --model CM     computer model deciding which masses feed the device (default CM1)
  --device NAME  device profile for the passivity bound (default: the scene's
                 device_profile; ergos, falcon)
  --json         print JSON instead: settings, stability, and the geometry (path
                 centerlines, widths, top heights, the body's grid offsets)
  --rate-sweep   also run the scene through each integrator at 1, 2, 5, 10, 20 and
                 44 kHz along its scripted hand path (enact path; a scene without a
                 task path: the hand held still for 1 s) and compare the force sent to
                 the device, and the pins, with a cordis run at 880 kHz at every step:
                 ns per step, force error (rms, max, N), share of steps whose pins
                 differ (JSON: rate_sweep). Takes seconds to a minute
)";

// the hand path of the sweep: the scripted path when the scene has a task path, else the
// body held at its position
struct SweepPath {
  reference::HandPath hand;
  double duration_s = 1.0;
};

SweepPath sweep_path(const std::string& scene, const physics::Model& m) {
  if (m.task_surface.empty()) {
    const math::Vec3 still = m.points[m.proxies[0].point].position_m;
    return {[still](double) { return still; }, 1.0};
  }
  sim::SimParams p;
  p.scene = scene;
  p.force = true;
  sim::Simulator simulator;
  simulator.configure(p);
  const task::Trajectory tr = sim::scripted_path(simulator);
  return {[tr](double t) { return tr.at(tr.start_s() + t); }, tr.end_s() - tr.start_s()};
}

void json_vec(Json& j, const math::Vec3& v) { j.begin_array().value(v.x).value(v.y).value(v.z).end_array(); }

void write_json(const physics::Model& m, const physics::StabilityReport& r, const std::string& device, const std::vector<reference::SweepRow>& sweep) {
  Json j;
  j.begin_object().field("scene", m.name).field("source", m.source).field("rate_hz", m.rate_hz).field("dt_s", m.dt_s);
  j.field("integrator", physics::to_string(m.integrator)).field("device_profile", device);
  j.field("stable", r.stable()).field("passive", r.passive());
  j.key("objects").begin_array();
  for (const auto& o : m.objects) {
    const bool boxes = o.type == physics::ObjectType::boxes && !o.is_path;
    j.begin_object().field("name", o.name).field("type", boxes ? "boxes" : o.is_path ? "path" : o.type == physics::ObjectType::plane ? "plane" : o.shape);
    if (o.type == physics::ObjectType::mesh) j.field("triangles", static_cast<double>(m.meshes[o.mesh].triangles.size()));
    if (o.type == physics::ObjectType::capsule) j.field("radius_m", o.radius_m);
    if (o.is_path) {
      j.key("centerline_m").begin_array();
      for (const auto& p : o.path.centerline_m) j.begin_array().value(p.x).value(p.y).end_array();
      j.end_array().field("width_m", o.path.width_m).field("top_z_m", o.path.top_z_m).field("bottom_z_m", o.path.bottom_z_m);
    }
    if (o.type == physics::ObjectType::plane) {
      j.key("point_m");
      json_vec(j, o.plane_point_m);
      j.key("normal");
      json_vec(j, o.plane_normal);
    }
    j.end_object();
  }
  j.end_array();
  j.key("bodies").begin_array();
  for (const auto& p : m.proxies) {
    j.begin_object().field("name", p.name).field("rows", p.rows).field("cols", p.cols).field("pitch_m", p.pitch_m);
    j.key("position_m");
    json_vec(j, m.points[p.point].position_m);
    j.key("offsets_m").begin_array();
    for (int i = 0; i < p.rows * p.cols; ++i) json_vec(j, m.points[p.first_body + i].offset_m);
    j.end_array().end_object();
  }
  j.end_array();
  j.key("masses").begin_array();
  for (const auto& s : r.masses) {
    j.begin_object().field("name", m.points[s.point].name).field("stiffness_n_per_m", s.stiffness_n_per_m);
    j.field("damping_n_s_per_m", s.damping_n_s_per_m).field("demand_n_per_m", s.demand).field("limit_n_per_m", s.limit);
    j.field("stable", s.stable).field("largest_element", s.largest_element);
    j.field("largest_stable_stiffness_n_per_m", s.largest_stable_stiffness_n_per_m).field("min_stable_rate_hz", s.min_stable_rate_hz).end_object();
  }
  j.end_array();
  j.key("deformable_bodies").begin_array();
  for (const auto& b : r.bodies) {
    j.begin_object().field("body", m.proxies[b.proxy].name).field("mass", m.points[b.point].name).field("step_s", b.step_s);
    j.field("max_step_s", std::isinf(b.max_step_s) ? -1.0 : b.max_step_s).field("stable", b.stable).end_object();
  }
  j.end_array();
  j.key("devices").begin_array();
  for (const auto& d : r.devices) {
    j.begin_object().field("body", m.proxies[d.proxy].name).field("stiffness_n_per_m", d.stiffness_n_per_m);
    j.field("damping_n_s_per_m", d.damping_n_s_per_m).field("required_n_s_per_m", d.required_n_s_per_m);
    j.field("device_damping_n_s_per_m", d.device_damping_n_s_per_m).field("passive", d.passive);
    j.field("largest_passive_stiffness_n_per_m", d.largest_passive_stiffness_n_per_m).field("min_passive_rate_hz", d.min_passive_rate_hz).end_object();
  }
  j.end_array();
  if (!sweep.empty()) {
    j.key("rate_sweep");
    sweep_json(j, sweep);
  }
  j.end_object();
  std::cout << j.str() << "\n";
}

// the bound live stiffness and damping changes are held to (the figure the viewer and every
// refusal give): every body point feeding, whatever the computer model
void print_live_envelope(const physics::Model& m) {
  std::printf("\nlive changes  enact param set keeps K T/2 + B with every body point feeding (any computer model may be switched to)\n"
              "              at most %.2f N s/m (the device damping b, or this scene as loaded if larger; %s)\n",
              sim::passivity_envelope(m), config::shipped("docs/parameters.md").c_str());
}

void print_deformable(const physics::Proxy& p) {
  const physics::DeformableBody& d = p.deformable;
  if (!d.enabled()) return;
  std::printf("            deformable: %d masses of %.4g kg; proxy links %.4g N/m, %.4g N s/m; grid links %.4g N/m, %.4g N s/m\n",
              p.rows * p.cols, d.mass_kg, d.proxy_stiffness_n_per_m, d.proxy_damping_n_s_per_m, d.grid_stiffness_n_per_m,
              d.grid_damping_n_s_per_m);
}

// a deformable body's bound on the step (physics::BodyStability)
void print_body_bound(const physics::Model& m, const physics::BodyStability& b) {
  std::printf("\ndeformable body %s: dt < 4m / (z + sqrt(z^2 + 4 K m)) over its masses (2 sqrt(m/K) undamped)\n", m.proxies[b.proxy].name.c_str());
  if (std::isinf(b.max_step_s)) {
    std::printf("  dt %.4g us, no bound (%s)  stable\n", b.step_s * 1e6, m.integrator == physics::Integrator::implicit_euler ? "implicit_euler" : "no stiffness");
    return;
  }
  std::printf("  dt %.4g us < %.4g us at %s (loop rate >= %.0f Hz), margin %.1f%%  %s\n", b.step_s * 1e6, b.max_step_s * 1e6,
              m.points[b.point].name.c_str(), std::ceil(1.0 / b.max_step_s), 100.0 * (1.0 - b.step_s / b.max_step_s),
              b.stable ? "stable" : "UNSTABLE");
}

void write_table(const physics::Model& m, const physics::StabilityReport& r, const std::string& device) {
  int dynamic = 0, fixed = 0, body = 0;
  for (const auto& p : m.points) {
    dynamic += p.kind == physics::PointKind::dynamic && p.proxy < 0;
    fixed += p.kind == physics::PointKind::fixed;
    body += p.proxy >= 0;
  }
  std::printf("scene       %s (%s)\n", m.name.c_str(), m.source.c_str());
  std::printf("loop        %.0f Hz (dt %.3g us), integrator %s\n", m.rate_hz, m.dt_s * 1e6, physics::to_string(m.integrator));
  std::printf("elements    %d masses, %d fixed points, %d body points, %zu links, %zu objects (%zu boxes), %zu contact pairs\n",
              dynamic, fixed, body, m.links.size(), m.objects.size(), m.boxes.size(), m.contacts.size());
  for (const auto& p : m.proxies) {
    std::printf("body        %s: %d x %d grid, pitch %.3g mm, centre at (%.4g, %.4g, %.4g) m\n", p.name.c_str(), p.rows, p.cols,
                p.pitch_m * 1e3, m.points[p.point].position_m.x, m.points[p.point].position_m.y, m.points[p.point].position_m.z);
    print_deformable(p);
  }
  std::printf("\nintegrator stability (%s)\n", m.integrator == physics::Integrator::implicit_euler ? "implicit: unconditional" : "explicit: K + 2Z < 4M, Z = z/dt, M = m/dt^2");
  if (r.masses.empty()) std::printf("  no dynamic masses (the body follows the device)\n");
  else std::printf("  %-16s %12s %12s %12s %8s  %s\n", "mass", "K+2Z (N/m)", "4M (N/m)", "min rate Hz", "margin", "verdict");
  for (const auto& s : r.masses) {
    std::printf("  %-16s %12.4g %12.4g %12.0f %7.1f%%  %s\n", m.points[s.point].name.c_str(), s.demand, s.limit,
                std::ceil(s.min_stable_rate_hz), 100.0 * (1.0 - s.demand / s.limit), s.stable ? "stable" : "UNSTABLE");
  }
  if (!r.devices.empty()) {
    std::printf("\ndevice passivity on %s (Colgate & Schenkel 1997: b > K T/2 + B)\n", device.c_str());
    std::printf("  %-10s %12s %10s %12s %10s %14s %12s  %s\n", "body", "K (N/m)", "B (N s/m)", "KT/2+B", "b (N s/m)", "max K (N/m)",
                "min rate Hz", "verdict");
    for (const auto& d : r.devices) {
      std::printf("  %-10s %12.4g %10.4g %12.4g %10.4g %14.4g %12.0f  %s\n", m.proxies[d.proxy].name.c_str(), d.stiffness_n_per_m,
                  d.damping_n_s_per_m, d.required_n_s_per_m, d.device_damping_n_s_per_m, d.largest_passive_stiffness_n_per_m,
                  std::ceil(d.min_passive_rate_hz), d.passive ? "passive" : "not guaranteed passive (warning)");
    }
  }
  for (const auto& b : r.bodies) print_body_bound(m, b);
  std::printf("\nverdict     %s\n", r.stable() ? "stable" : "UNSTABLE");
}

}  // namespace

int check(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"rate", "model", "device"}, {"json", "rate-sweep"});
  if (a.flag("help")) {
    std::fputs(kCheckHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one scene file");
  physics::Model m = physics::load_scene(a.positional[0]);
  if (a.has("rate")) {
    const double rate = a.number("rate", 0.0);
    if (rate < 1.0 || rate > 1.0e6) throw UsageError("--rate must be from 1 to 1000000 Hz");
    m.set_rate(rate);
  }
  if (a.flag("rate-sweep") && m.proxies.empty()) throw config::Error(m.source + ": --rate-sweep compares the force sent to the device: the scene has no body\n  fix: add a body: section");
  haptics::ComputerModel cm;
  if (!m.proxies.empty()) {
    cm = haptics::resolve_computer_model(a.get("model", "CM1"), m.proxies[0].rows * m.proxies[0].cols);
    haptics::apply(cm, m);
  }
  const std::string device = a.get("device", m.device_profile);
  double b = -1.0;
  if (!device.empty()) {
    const auto profile = devices::find_device_profile(device);
    if (!profile) throw UsageError("unknown device profile '" + device + "' (ergos, falcon)");
    b = profile->damping_n_s_per_m;
  }
  const physics::StabilityReport r = physics::analyze_stability(m, b);
  std::vector<reference::SweepRow> sweep;
  if (a.flag("rate-sweep")) {
    const SweepPath path = sweep_path(a.positional[0], m);
    const reference::PinsOf pins = [&cm](const physics::Model& model, const physics::State& s) { return haptics::pins(cm, model, s); };
    sweep = reference::rate_sweep(m, pins, path.hand, path.duration_s, reference::kSweepReference_hz);
  }
  if (a.flag("json")) write_json(m, r, device, sweep);
  else write_table(m, r, device);
  if (!a.flag("json") && !m.proxies.empty()) print_live_envelope(m);
  if (!sweep.empty() && !a.flag("json")) print_sweep(sweep, "rate sweep: device force and pins against cordis at 880 kHz");
  std::fflush(stdout);  // the table before any message on stderr
  if (!r.stable()) {
    std::fprintf(stderr, "enact check: %s\n", physics::instability_message(m, r).c_str());
    return 1;
  }
  if (!r.passive() && !a.flag("json")) std::fprintf(stderr, "enact check: warning: %s\n", physics::passivity_message(m, r, device).c_str());
  return 0;
}

}  // namespace enact::cli
