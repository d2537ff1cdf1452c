#include "core/experiment/virtual_trial.h"

#include <cmath>
#include <cstring>

#include "core/devices/virtual_subject.h"
#include "core/node/colocated.h"
#include "core/node/components.h"
#include "core/params/node_params.h"

namespace enact::experiment {
namespace {

// the synthetic clock of the loop (ColocatedLoop takes a plain function)
thread_local std::int64_t t_clock_ns = 0;
std::int64_t synthetic_clock() { return t_clock_ns; }

// FNV-1a over the bytes of a value
void mix(std::uint64_t& hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ULL;
}

}  // namespace

VirtualTrialResult run_virtual_trial(const VirtualTrialParams& params) {
  sim::SimParams sp = graph::sim_params(params.sim);
  sp.rate_hz = params.rate_hz;
  sim::Simulator simulator;
  simulator.configure(sp);
  auto force = graph::make_force_device(params.ffd);
  auto tactile = graph::make_tactile_device(params.tactile);
  params.sim.refuse_unknown();
  params.ffd.refuse_unknown();
  params.tactile.refuse_unknown();

  graph::ColocatedLoop loop(simulator, *force, tactile.get(), &synthetic_clock);
  const std::int64_t period_ns = std::llround(1e9 / params.rate_hz);
  const std::int64_t ticks = std::llround(params.limit_s * params.rate_hz);
  VirtualTrialResult result;
  result.hash = 0xcbf29ce484222325ULL;
  loop.activate();
  for (std::int64_t n = 0; n < ticks; ++n) {
    t_clock_ns = n * period_ns;
    const graph::Observation& o = loop.tick(n * period_ns);
    mix(result.hash, &o.sample.position_m, sizeof o.sample.position_m);
    mix(result.hash, &o.step.force_n, sizeof o.step.force_n);
    result.ticks = n + 1;
    if (o.step.event.kind == task::TaskEventKind::completed) break;
  }
  loop.deactivate();
  result.metrics = simulator.metrics();
  if (const auto* subject = dynamic_cast<const devices::VirtualSubject*>(force->simulated_hand())) {
    result.losses = subject->losses();
    result.repositions = subject->repositions();
  }
  return result;
}

}  // namespace enact::experiment
