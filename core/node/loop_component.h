#pragma once
// Loop components a user writes: a stage between the model's step and the force's write, in
// the co-located tick (enact-rt) or in the distributed simulator's answer (enact-sim). Each tick the loop reads the device, steps the model, then calls
// every stage in the order of the launch file's component list, then writes the force and
// the pins the stages leave: a stage may add a guiding spring, filter the force, gate the
// pins, or just watch. The device's safety layer (force and step limits, NaN, watchdog) still
// holds after the stages, and observers see the force that was written.
//
// A stage is a class with configure (its constructor, from its parameters), activate, step and
// deactivate, built into a shared library that enact-rt or enact-sim loads (launch file: component entry
// `library:`; command line: --library=PATH). The library exports two C functions:
//
//   extern "C" int enact_plugin_abi() { return enact::node::kPluginAbi; }
//   extern "C" void enact_register_plugins(enact::node::PluginRegistry& r) { r.add(kMyStage); }
//
// examples/plugins/guide_spring.cpp is a whole one (docs/components.md says how to build it).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/devices/device.h"
#include "core/params/param_table.h"
#include "core/params/params.h"
#include "core/sim/simulator.h"

namespace enact::node {

// raised when this header's types change shape: a library built against another one is refused
inline constexpr int kPluginAbi = 1;

// what a stage sees of one tick
struct Tick {
  std::int64_t time_ns = 0;        // the tick's time on the graph clock (its deadline)
  std::int64_t model_time_ns = 0;  // the model's time: 0 at the first tick
  const devices::ForceSample* sample = nullptr;  // what the device read this tick
  sim::StepOutput* step = nullptr;  // what the model made of it; force_n (N) and frame (the pins
                                    // written when frame_due) are the stage's to change
};

class LoopComponent {
 public:
  virtual ~LoopComponent() = default;
  // before the first tick, on the loop's thread (the loop is not yet timed)
  virtual void activate() {}
  // each tick, on the real-time thread: allocate nothing, lock nothing, never block, never
  // read a file, never throw
  virtual void step(Tick& tick) noexcept = 0;
  // after the last tick, once the device's force is zeroed and the pins lowered
  virtual void deactivate() noexcept {}
};

// a kind of stage: what a launch file names in `plugin:`
struct LoopPlugin {
  const char* plugin;  // its name in a launch file (component: plugin:) and on --component
  const char* what;    // one line, for --help and refusals
  const graph::ParamTable& (*table)();  // its parameters (their values reach make, checked)
  // the stage configured from its parameters (scoped: "gain", not "name.gain"); throws
  // config::Error (or any std::exception) for input it refuses, before anything moves
  std::unique_ptr<LoopComponent> (*make)(const graph::Params& params);
};

// what a library's enact_register_plugins adds its stages to
struct PluginRegistry {
  std::vector<LoopPlugin> plugins;
  void add(const LoopPlugin& p) { plugins.push_back(p); }
};

// loads the shared library at `path` and registers its stages (graph::component_kinds() then
// lists them, role stage); a library already loaded is not loaded again. Throws config::Error
// naming the file and the fix (not found, not a plugin, built against another kPluginAbi, a
// plugin name already taken)
void load_plugin_library(const std::string& path);

// a stage of a loaded library, configured from its parameters (nullptr: no such plugin)
std::unique_ptr<LoopComponent> make_stage(const std::string& plugin, const graph::Params& params);

}  // namespace enact::node
