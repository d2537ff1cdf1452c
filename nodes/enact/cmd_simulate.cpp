// enact simulate / enact path: offline runs of the simulator component.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "core/config/share.h"
#include "core/config/yaml.h"
#include "core/sim/offline.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kSimulateHelp = R"(usage: enact simulate SCENE [--input PATH.csv] [--model CM1[,CM2...]] [--rate HZ]
                      [--out OUT.csv] [--metrics M.json] [--tactile-period S]
                      [--tactile-mode sample|any] [--force]

Offline and deterministic, no processes: device positions from PATH.csv (columns
t_s,x_m,y_m,z_m, linearly interpolated to the rate) drive the body through the scene;
each step gives the force, the contacts, the pins and the task state. Identical input
gives byte-identical output. Prints one summary row per computer model.

options:
  --input PATH.csv     device path (default: the scene's built-in scripted hand path,
                       see `enact path`)
  --model LIST         computer models, comma separated: presets CM0 CM1 CM2 CM3 P T PT,
                       YAML files, or `all` for every preset (default CM1)
  --rate HZ            loop rate, 1 to 44000 Hz (default: the scene's rate_hz)
  --out OUT.csv        one row per step: t_s,x_m,y_m,z_m,fx_n,fy_n,fz_n,contacts,pins,
                       on_top,progress,fault (pins: 0/1 per pin, row-major); one model only
  --metrics M.json     trial metrics: falls, time_total_s, time_out_s, ratio, completed...
  --tactile-period S   tactile frame period (default 0.024 s: the cells' rise time)
  --tactile-mode MODE  sample: pins of the frame's step; any: up if up at any step since
                       the last frame (default sample)
  --force              run a scene that fails the stability check anyway
)";

constexpr const char* kPathHelp = R"(usage: enact path SCENE [-o OUT.csv] [--press M]

Write the built-in scripted hand path of a scene with a task path (the bridge): pressed
0.05 mm into the top at 10 mm/s with a small lateral wobble, one slide off the edge for
under 1 s (not a fall) and one for about 2 s (a fall), then on to the end. Columns
t_s,x_m,y_m,z_m at 100 Hz; edit it and pass it to `enact simulate --input`, or give it to
a simulated device as the target of its scripted hand (ffd.hand_path).

options:
  --press M   how deep below the top the path runs (m; default 0.00005). A device moved by
              a hand spring needs a deeper target to press: 0.003 gives about 0.9 N at
              300 N/m (launch/paths/bridge_walk.csv)
)";

std::ofstream open_out(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw config::Error(path + ": cannot write the file\n  fix: check that the folder exists and is writable");
  return out;
}

sim::SimParams params_from(const Args& a, const std::string& model) {
  sim::SimParams p;
  p.scene = a.positional.at(0);
  p.rate_hz = a.number("rate", 0.0);
  if (a.has("rate") && (p.rate_hz < 1.0 || p.rate_hz > 44000.0)) throw UsageError("--rate must be from 1 to 44000 Hz");
  p.model = model;
  p.tactile.period_s = a.number("tactile-period", p.tactile.period_s);
  if (p.tactile.period_s <= 0.0) throw UsageError("--tactile-period must be > 0");
  if (a.has("tactile-mode")) {
    try {
      p.tactile.mode = haptics::parse_tactile_mode(a.get("tactile-mode"));
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  p.force = a.flag("force");
  return p;
}

// the table's two header lines and its rows; the task's columns only for a scene with a task
void print_header(bool task) {
  std::printf("%-6s %10s %10s %10s %10s", "model", "mean |F|", "peak |F|", "pins up", "contact");
  if (task) std::printf(" %6s %10s %10s %6s", "falls", "time_out", "time_total", "done");
  std::printf(" %6s\n%-6s %10s %10s %10s %10s", "faults", "", "(N)", "(N)", "(mean)", "(% steps)");
  if (task) std::printf(" %6s %10s %10s %6s", "", "(s)", "(s)", "");
  std::printf(" %6s\n", "");
}

void print_row(const sim::RunSummary& s, bool task) {
  const task::Metrics& m = s.metrics;
  std::printf("%-6s %10.3f %10.3f %10.2f %10.1f", s.model.c_str(), s.mean_force_n, s.peak_force_n, s.mean_pins_up, 100.0 * s.contact_fraction);
  if (task) std::printf(" %6d %10.3f %10.3f %6s", m.falls, m.time_out_s, m.time_total_s, m.completed ? "yes" : "no");
  std::printf(" %6llu\n", static_cast<unsigned long long>(s.faults));
}

}  // namespace

int simulate(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"input", "model", "rate", "out", "metrics", "tactile-period", "tactile-mode"}, {"force"});
  if (a.flag("help")) {
    std::fputs(kSimulateHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one scene file");
  std::vector<std::string> models = split_commas(a.get("model", "CM1"));
  if (models.size() == 1 && models[0] == "all") models = haptics::preset_names();
  if (models.empty()) throw UsageError("--model needs at least one computer model");
  if (models.size() > 1 && (a.has("out") || a.has("metrics"))) throw UsageError("--out and --metrics take a single --model");

  // every model checked before the table starts; a scene without a task has no task columns
  for (const std::string& model : models) haptics::resolve_computer_model(model);
  sim::Simulator first;
  first.configure(params_from(a, models.front()));
  const bool task = first.has_task();
  print_header(task);
  std::vector<std::string> not_done;  // why each run that did not complete did not
  for (const std::string& model : models) {
    sim::Simulator simulator;
    simulator.configure(params_from(a, model));
    const task::Trajectory path = a.has("input") ? task::load_trajectory(a.get("input")) : sim::scripted_path(simulator);
    std::ofstream csv;
    if (a.has("out")) csv = open_out(a.get("out"));
    const sim::RunSummary s = sim::run_offline(simulator, path, a.has("out") ? &csv : nullptr);
    print_row(s, task);
    if (const std::string why = sim::not_done_reason(s, simulator); !why.empty()) not_done.push_back(why);
    if (a.has("metrics")) {
      std::ofstream out = open_out(a.get("metrics"));
      sim::write_metrics_json(s, simulator, out);
    }
  }
  if (!task) std::printf("(no task in this scene: no falls, time out or completion to count)\n");
  for (const std::string& why : not_done) std::printf("%s\n", why.c_str());
  if (a.has("input")) {
    std::printf("(the device followed the path exactly; live, a simulated hand tracks it behind a spring and presses far less:\n"
                " %s, \"Offline and live forces differ\")\n", config::shipped("docs/scenes-and-models.md").c_str());
  }
  return 0;
}

int path(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"out", "press"}, {});
  if (a.flag("help")) {
    std::fputs(kPathHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one scene file");
  sim::SimParams p;
  p.scene = a.positional[0];
  p.force = true;
  sim::Simulator simulator;
  simulator.configure(p);
  const double press = a.number("press", 0.00005);
  if (press < 0.0 || press > 0.01) throw UsageError("--press must be from 0 to 0.01 m");
  const task::Trajectory tr = sim::scripted_path(simulator, press);
  if (!a.has("out")) {
    task::write_trajectory(tr, std::cout);
    return 0;
  }
  std::ofstream out = open_out(a.get("out"));
  task::write_trajectory(tr, out);
  std::fprintf(stderr, "wrote %s: %zu samples, %.1f s\n", a.get("out").c_str(), tr.t_s.size(), tr.end_s());
  return 0;
}

}  // namespace enact::cli
