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

struct RunSummary {
  std::string model;
  std::int64_t steps = 0;
  std::uint64_t faults = 0;
  double mean_force_n = 0.0;    // mean |F| over all steps
  double peak_force_n = 0.0;    // max |F|
  double mean_pins_up = 0.0;    // mean number of raised pins over all steps
  double contact_fraction = 0.0;  // fraction of steps with a grid mass touching
  task::Metrics metrics;
};

// one step per 1/rate from the trajectory's start to its end; writes one CSV row per step
// when csv is not null
RunSummary run_offline(Simulator& simulator, const task::Trajectory& trajectory, std::ostream* csv);
void write_metrics_json(const RunSummary& summary, const Simulator& simulator, std::ostream& out);

}  // namespace enact::sim
