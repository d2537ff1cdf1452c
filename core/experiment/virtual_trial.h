#pragma once
// A trial in simulated time: the co-located tick of enact-rt (the same simulator, simulated
// devices and graph::ColocatedLoop, built from the same node parameters) driven by a
// synthetic clock, as fast as the machine goes. With a virtual subject holding the device it
// is bit-for-bit reproducible, so it serves the tests and the tuning of subjects; the
// experiment runner itself runs real graphs (core/experiment/runner.h).
#include <cstdint>

#include "core/params/params.h"
#include "core/task/bridge_task.h"

namespace enact::experiment {

struct VirtualTrialParams {
  graph::Params sim;       // the sim component's params (scene, model, ...)
  graph::Params ffd;       // the ffd component's params (subject, seeds, start_m, ...)
  graph::Params tactile;   // the tactile component's params
  double rate_hz = 5000.0; // loop rate
  double limit_s = 180.0;  // the trial stops here if the bridge is not completed
};

struct VirtualTrialResult {
  task::Metrics metrics;
  std::int64_t ticks = 0;
  int losses = 0;          // times the subject felt it had fallen off (a virtual subject only)
  int repositions = 0;     // times it was put back at the start
  std::uint64_t hash = 0;  // of every tick's device sample and force: equal runs, equal hashes
};

// runs one trial until the task completes or the limit; throws config::Error on bad params
VirtualTrialResult run_virtual_trial(const VirtualTrialParams& params);

}  // namespace enact::experiment
