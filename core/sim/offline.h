#pragma once
// Offline simulation: a device trajectory from CSV (or the built-in scripted path) through
// the simulator component, no processes, deterministic: identical input gives
// byte-identical output.
#include <iosfwd>
#include <string>
#include <vector>

#include "core/task/trajectory.h"
#include "core/physics/model.h"
#include "core/sim/simulator.h"

namespace enact::sim {


// a scripted hand along the task path of the scene (docs/scenes-and-models.md, "The scripted path"): it presses
// press_m into the top (a kinematic device: 0.05 mm; a hand target behind a spring: deeper), wobbles, slides off the edge once briefly (under 1 s: not a fall) and once for
// about 2 s (a fall), climbs back, and reaches the end
task::Trajectory scripted_path(const Simulator& simulator, double press_m = 0.00005);

// can a device (or a hand's target) moving along `path` bring the scene's exploratory body to
// anything it has contacts with? Conservative: false only when, along every segment of the
// path, a sphere holding the whole body (and margin_m more) stays clear of each such object.
// A body with contact links to the scene's masses may always touch (not checked)
bool path_may_touch(const physics::Model& model, const task::Trajectory& path, double margin_m = 0.002);

// the warning for a scripted hand whose path never touches the scene, with the fix ("" when
// it may touch it); reads both files (throws config::Error as loading them does)
std::string hand_path_warning(const std::string& scene_file, const std::string& path_file);

struct RunSummary {
  std::string model;
  std::int64_t steps = 0;
  std::uint64_t faults = 0;
  double mean_force_n = 0.0;    // mean |F| over all steps
  double peak_force_n = 0.0;    // max |F|
  double mean_pins_up = 0.0;    // mean number of raised pins over all steps
  double contact_fraction = 0.0;  // fraction of steps with a grid mass touching
  double path_progress = 0.0;     // the furthest progress along the task path, on the top or not
  task::Metrics metrics;
};

// one step per 1/rate from the trajectory's start to its end; writes one CSV row per step
// when csv is not null
RunSummary run_offline(Simulator& simulator, const task::Trajectory& trajectory, std::ostream* csv);
// why a run on a scene with a task did not complete, in words ("" when it did, or there is
// no task): the path's progress against the progress made on the top
std::string not_done_reason(const RunSummary& summary, const Simulator& simulator);
void write_metrics_json(const RunSummary& summary, const Simulator& simulator, std::ostream& out);

}  // namespace enact::sim
