#include "core/sim/offline.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <ostream>
#include <sstream>

#include "core/config/format.h"
#include "core/config/share.h"
#include "core/physics/contact.h"
#include "core/physics/scene.h"
#include "core/config/share.h"
#include "core/config/yaml.h"

namespace enact::sim {
namespace {

using config::number;

// scripted hand: a timeline of keyframes in path coordinates (arc length, lateral offset,
// height above the top), linearly interpolated
struct Key {
  double t_s;
  double s_m;
  double lateral_m;
  double dz_m;
  bool wobble;
};

}  // namespace

task::Trajectory scripted_path(const Simulator& sim, double press) {
  if (!sim.has_task()) throw config::Error(sim.model().source + ": the scene has no task path\n  fix: add task: {surface: <object>} (" + config::shipped("docs/scenes-and-models.md") + ", \"The task\") or give --input");
  const physics::PathGeometry& along = sim.model().task_path;
  const task::Polyline& path = sim.path();
  const double length = path.length_m();
  const double top = along.top_z_m;
  const double speed = 0.010;                  // 10 mm/s along the path
  const physics::Proxy& body = sim.model().proxies[0];
  const double body_half = body.pitch_m * std::hypot(body.rows - 1, body.cols - 1) / 2.0;  // any orientation
  const double off_edge = along.width_m / 2 + body_half + 0.001;  // whole grid off the top
  const double above = 0.001;
  std::vector<Key> keys;
  double t = 0.0, s = 0.002;
  auto add = [&](double dt, double lateral, double dz, bool wobble) {
    t += dt;
    keys.push_back({t, s, lateral, dz, wobble});
  };
  auto travel_to = [&](double s_to) {
    const double dt = (s_to - s) / speed;
    s = s_to;
    add(dt, 0.0, -press, true);
  };
  // slide off sideways, stay off (sinking by `drop`), climb over the edge and land back on the top
  auto excursion = [&](double off_s, double drop) {
    add(0.15, off_edge, -press, false);
    add(0.05, off_edge, -press - drop, false);
    add(off_s, off_edge, -press - drop, false);
    add(0.05, off_edge, above, false);
    add(0.10, 0.0, above, false);
    add(0.05, 0.0, -press, false);
  };
  keys.push_back({0.0, s, 0.0, above, false});
  add(0.3, 0.0, -press, false);
  // off the outer side in the middle of the 1st and 2nd segments
  travel_to(length / 6.0);
  excursion(0.05, 0.0);   // off the top for about 0.3 s: not a fall
  travel_to(length / 2.0);
  excursion(1.6, 0.003);  // off for about 2 s: a fall
  travel_to(length);
  add(0.3, 0.0, -press, false);

  task::Trajectory tr;
  const double sample_s = 0.01;
  std::size_t k = 1;
  for (double time = 0.0; time <= t + 1e-9; time += sample_s) {
    while (k + 1 < keys.size() && keys[k].t_s < time) ++k;
    const Key& a = keys[k - 1];
    const Key& b = keys[k];
    const double w = std::clamp((time - a.t_s) / (b.t_s - a.t_s), 0.0, 1.0);
    const double arc = a.s_m + (b.s_m - a.s_m) * w;
    double lateral = a.lateral_m + (b.lateral_m - a.lateral_m) * w;
    if (b.wobble) lateral += 0.0008 * std::sin(2.0 * std::numbers::pi * 0.7 * time);
    const task::Point2 c = path.at(arc);
    const task::Point2 d = path.direction_at(arc);
    const double z = top + a.dz_m + (b.dz_m - a.dz_m) * w;
    tr.t_s.push_back(time);
    // lateral is to the right of the direction of travel
    tr.position_m.push_back({c.x_m + d.y_m * lateral, c.y_m - d.x_m * lateral, z});
  }
  return tr;
}

RunSummary run_offline(Simulator& sim, const task::Trajectory& tr, std::ostream* csv) {
  RunSummary sum;
  sum.model = sim.computer_model().name;
  const double dt = sim.model().dt_s;
  const auto steps = static_cast<std::int64_t>(std::floor((tr.end_s() - tr.start_s()) / dt + 1e-9)) + 1;
  const int masses = sim.grid_masses();
  if (csv) *csv << "t_s,x_m,y_m,z_m,fx_n,fy_n,fz_n,contacts,pins,on_top,progress,fault\n";
  std::string pins(static_cast<std::size_t>(masses), '0');
  sim.activate(0);
  double force_sum = 0.0, pins_sum = 0.0;
  std::int64_t touching = 0;
  for (std::int64_t n = 0; n < steps; ++n) {
    const double t = static_cast<double>(n) * dt;
    const math::Vec3 p = tr.at(tr.start_s() + t);
    const StepOutput& o = sim.step(static_cast<std::int64_t>(std::llround(t * 1e9)), p);
    const double f = math::norm(o.force_n);
    force_sum += f;
    sum.peak_force_n = std::max(sum.peak_force_n, f);
    pins_sum += std::popcount(o.pins);
    touching += o.contacts > 0;
    sum.path_progress = std::max(sum.path_progress, o.progress);
    if (!csv) continue;
    for (int i = 0; i < masses; ++i) pins[static_cast<std::size_t>(i)] = (o.pins >> i) & 1u ? '1' : '0';
    *csv << number(t) << ',' << number(p.x) << ',' << number(p.y) << ',' << number(p.z) << ',' << number(o.force_n.x) << ','
         << number(o.force_n.y) << ',' << number(o.force_n.z) << ',' << o.contacts << ',' << pins << ',' << (o.on_top ? 1 : 0)
         << ',' << number(o.progress) << ',' << (o.fault ? 1 : 0) << '\n';
  }
  sum.steps = steps;
  sum.faults = sim.state().faults;
  sum.mean_force_n = force_sum / static_cast<double>(steps);
  sum.mean_pins_up = pins_sum / static_cast<double>(steps);
  sum.contact_fraction = static_cast<double>(touching) / static_cast<double>(steps);
  sum.metrics = sim.metrics();
  return sum;
}

bool path_may_touch(const physics::Model& model, const task::Trajectory& path, double margin_m) {
  if (model.proxies.empty() || path.t_s.empty()) return true;
  const physics::Proxy& body = model.proxies[0];
  for (const physics::Link& l : model.links) {
    if (l.type == physics::LinkType::contact && (model.points[l.a].proxy == 0 || model.points[l.b].proxy == 0)) return true;
  }
  // a deformable body's masses sway about their rest places
  if (body.deformable.enabled()) margin_m += body.pitch_m;
  // each contact pair of a body point, along each segment of the path: a sphere about the
  // point's place at the segment's middle, holding both ends
  for (std::size_t i = 0; i < path.position_m.size(); ++i) {
    const math::Vec3& a = path.position_m[i];
    const math::Vec3& b = path.position_m[i + 1 < path.position_m.size() ? i + 1 : i];
    const math::Vec3 middle = (a + b) * 0.5;
    const double radius_m = margin_m + 0.5 * math::norm(b - a);
    for (const physics::ContactPair& c : model.contacts) {
      const physics::Point& point = model.points[c.point];
      if (point.proxy == 0 && !physics::apart(model, model.objects[c.object], middle + point.offset_m, radius_m)) return true;
    }
  }
  return false;
}

std::string hand_path_warning(const std::string& scene_file, const std::string& path_file) {
  const physics::Model model = physics::load_scene(scene_file);
  if (path_may_touch(model, task::load_trajectory(path_file))) return "";
  std::string fix = model.task_surface.empty()
                        ? "give a path that reaches the scene: --arg hand_path=PATH.csv (t_s,x_m,y_m,z_m; " + config::shipped("docs/scenes-and-models.md") + ")"
                        : "the scene's own path: enact path " + scene_file + " -o path.csv, then --arg hand_path=path.csv";
  return "the hand path " + path_file + " never comes near the scene " + scene_file + " (its body stays clear of every object it has contacts with): "
         "nothing will be felt\n  fix: " + fix;
}

std::string not_done_reason(const RunSummary& s, const Simulator& sim) {
  const task::Metrics& m = s.metrics;
  if (!sim.has_task() || m.completed) return "";
  const double end = sim.params().task.end_progress;
  char text[400];
  if (s.path_progress >= end) {
    std::snprintf(text, sizeof text,
                  "not done (%s): progress along the path reached %.2f, but on the top of '%s' only %.2f: the trial completes at %.2f while on the top, "
                  "and the body was off it (or its points missed the top's faces) past there",
                  s.model.c_str(), s.path_progress, sim.model().task_surface.c_str(), m.progress, end);
  } else {
    std::snprintf(text, sizeof text, "not done (%s): the path ends at progress %.2f (on the top: %.2f); the trial completes at %.2f while on the top of '%s'",
                  s.model.c_str(), s.path_progress, m.progress, end, sim.model().task_surface.c_str());
  }
  return text;
}

void write_metrics_json(const RunSummary& s, const Simulator& sim, std::ostream& out) {
  const task::Metrics& m = s.metrics;
  out << "{\n"
      << "  \"scene\": \"" << sim.model().name << "\",\n"
      << "  \"model\": \"" << s.model << "\",\n"
      << "  \"rate_hz\": " << number(sim.model().rate_hz) << ",\n"
      << "  \"steps\": " << s.steps << ",\n"
      << "  \"faults\": " << s.faults << ",\n"
      << "  \"task\": " << (sim.has_task() ? "true" : "false") << ",\n";
  // the task's metrics only for a scene with a task (none to count without one)
  if (sim.has_task()) {
    out << "  \"falls\": " << m.falls << ",\n"
        << "  \"time_total_s\": " << number(m.time_total_s) << ",\n"
        << "  \"time_out_s\": " << number(m.time_out_s) << ",\n"
        << "  \"ratio\": " << number(m.ratio) << ",\n"
        << "  \"completed\": " << (m.completed ? "true" : "false") << ",\n"
        << "  \"progress\": " << number(m.progress) << ",\n";
  }
  out << "  \"mean_force_n\": " << number(s.mean_force_n) << ",\n"
      << "  \"peak_force_n\": " << number(s.peak_force_n) << ",\n"
      << "  \"mean_pins_up\": " << number(s.mean_pins_up) << ",\n"
      << "  \"contact_fraction\": " << number(s.contact_fraction) << "\n"
      << "}\n";
}

}  // namespace enact::sim
