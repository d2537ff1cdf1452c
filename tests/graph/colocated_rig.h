#pragma once
// The co-located tick's test rig: the bridge with a simulated ERGOS whose scripted hand walks
// the shipped path, simulated cells, and the loop ticking on a fake clock (the co-located
// tests' and the no-jolt tests').
#include <memory>
#include <string>
#include <vector>

#include "core/devices/safety.h"
#include "core/devices/simulated_force.h"
#include "core/devices/simulated_tactile.h"
#include "core/node/colocated.h"
#include "tests/support/test_util.h"

namespace enact::graph::rig {

// the force's write time the loop reads, set by Rig::tick
inline std::int64_t g_clock_ns = 0;
inline std::int64_t fake_clock() { return g_clock_ns; }

inline constexpr std::int64_t kPeriod_ns = 200'000;  // 5 kHz

// the bridge with a simulated ERGOS whose hand walks the shipped path, and simulated cells
// (or no tactile device)
struct Rig {
  sim::Simulator simulator;
  devices::SimulatedForceDevice* device = nullptr;  // inside the safety layer
  std::unique_ptr<devices::ForceDevice> force;
  devices::SimulatedTactileDevice tactile;
  std::unique_ptr<ColocatedLoop> loop;

  // stages: the loop's, in order (they outlive the rig)
  // safety_reengage_s: the safety layer's ramp back after an interruption (the graph's: 0.1 s;
  // 0: the force of every tick is the model's)
  explicit Rig(const std::string& model, bool with_tactile = true, const std::vector<node::LoopComponent*>& stages = {},
               double safety_reengage_s = 0.0) {
    sim::SimParams p;
    p.scene = test::source_path("launch/scenes/bridge.yaml");
    p.model = model;
    simulator.configure(p);
    devices::SimulatedForceParams f;
    f.hand_path = test::source_path("launch/paths/bridge_walk.csv");
    f.start_m = {-0.0074246, -0.0222739, 0.013};
    auto inner = std::make_unique<devices::SimulatedForceDevice>(f);
    device = inner.get();
    force = std::make_unique<devices::SafeForceDevice>(std::move(inner), devices::SafetyParams{.reengage_s = safety_reengage_s});
    force->configure();
    tactile.configure();
    loop = std::make_unique<ColocatedLoop>(simulator, *force, with_tactile ? &tactile : nullptr, &fake_clock);
    for (node::LoopComponent* stage : stages) loop->add_stage(*stage);
    loop->activate();
  }

  // the tick of period n (5 kHz), or of a sample at t_ns
  const Observation& tick(std::int64_t n) { return tick_at(n * kPeriod_ns); }
  const Observation& tick_at(std::int64_t t_ns) {
    g_clock_ns = t_ns + 1000;  // the force is written 1 us after the sample
    return loop->tick(t_ns);
  }
};

}  // namespace enact::graph::rig
