#pragma once
// Every node's and container component's parameters, declared once (param_table.h): what
// each node's --help lists, what it accepts at start, what `enact launch --check` checks in a
// launch file before anything starts, and what `enact param list` shows of a running graph.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/params/param_table.h"
#include "core/launch/launch_file.h"

namespace enact::sim {
struct SimParams;
}

namespace enact::graph {

template <class Config>
class ParamBindings;  // param_binding.h

// the simulator's parameters bound to the fields of sim::SimParams (graph::sim_params reads them)
const ParamBindings<sim::SimParams>& sim_bindings();
// the simulator's parameters as given
class Params;
sim::SimParams sim_params(const Params& p);
// the devices', bound to ForceConfig and TactileConfig (device_config.h; make_force_device and
// make_tactile_device read them)
struct ForceConfig;
struct TactileConfig;
const ParamBindings<ForceConfig>& force_bindings();
const ParamBindings<TactileConfig>& tactile_bindings();
// the node processes' own parameters, bound to their plumbing's structs (device_config.h)
struct SimNodeConfig;
struct FfdNodeConfig;
struct TactileNodeConfig;
struct RtConfig;
const ParamBindings<SimNodeConfig>& sim_node_bindings();
const ParamBindings<FfdNodeConfig>& ffd_node_bindings();
const ParamBindings<TactileNodeConfig>& tactile_node_bindings();
// the co-located container's own (enact-rt; its loop thread's CPU, `cpus`, is read by name:
// empty means any)
const ParamBindings<RtConfig>& rt_bindings();
// the observers' own, bound to LoggerConfig and FoxgloveConfig (device_config.h)
struct LoggerConfig;
struct FoxgloveConfig;
const ParamBindings<LoggerConfig>& logger_bindings();
const ParamBindings<FoxgloveConfig>& foxglove_bindings();

// the components of a real-time container (enact-rt) and of the nodes that wrap one
const ParamTable& sim_table();      // the simulator (plugin sim; enact-sim): sim_bindings()'s table
const ParamTable& force_table();    // the force device (plugin ffd; enact-ffd)
const ParamTable& tactile_table();  // the tactile device (plugin tactile; enact-tactile)
// a component's table by plugin name (nullptr: no such plugin)
const ParamTable* component_table(const std::string& plugin);

// what a component of a real-time container does: in the co-located tick, step the model, read
// the force device and write its force, write the pins, or change the force and pins between
// the model's step and their write (a stage a user writes, from a plugin library:
// node/loop_component.h); beside the loop, on a thread of its own, observe the graph (a
// logger, a Foxglove bridge: node/recorder.h)
enum class ComponentRole : std::uint8_t { model, force_device, tactile_device, observer, stage };
struct ComponentKind {
  const char* plugin;  // its name in a launch file (component: plugin:) and on --component
  ComponentRole role;
  const char* what;    // for help and refusals
  const ParamTable& (*table)();
  bool required;       // a container cannot run without one (the tactile display is optional)
};
// every kind of component a container (enact-rt) hosts, in the order of its --help: the
// built-in ones, then the stages of the plugin libraries loaded
const std::vector<ComponentKind>& component_kinds();
// a stage from a plugin library (node::load_plugin_library); false when the name is taken
bool add_component_kind(const ComponentKind& kind);
const ComponentKind* find_component_kind(const std::string& plugin);

// a container's component list (name, plugin), checked: each plugin known, at most one
// component of each loop role (observers and stages: any number) and one of each required role (enact-rt's one tick reads one force
// device, steps one model and, if it has one, writes one tactile display). The first problem, "what\n  fix: ..." (the plugins there are named), and the
// entry it is about (npos: the list as a whole); nullopt when the list can run
struct ComponentProblem {
  std::size_t entry = static_cast<std::size_t>(-1);
  std::string text;
};
std::optional<ComponentProblem> component_list_problem(const std::vector<std::pair<std::string, std::string>>& components);
// the component list of a node (not a container) run by executable `exec`: only enact-sim
// hosts components, and only stages (it runs its own simulator; its driver is another
// process): the first problem, as above
std::optional<ComponentProblem> stage_list_problem(const std::string& exec, const std::vector<std::pair<std::string, std::string>>& components);

// a node's own table by executable name (enact-sim: its component's and its own, enact-rt:
// the container's own); nullptr for an executable that declares none
const ParamTable* node_table(const std::string& exec);

// the parameters of every node and component of `graph` checked against their tables, each
// problem "FILE:LINE: node 'NAME': parameter 'P' ...\n  fix: ..." (the line of the
// parameter, or of the --arg it came from); empty when all are declared and valid
std::vector<std::string> check_params(const launch::LaunchDescription& graph);

// in simulated time (graph.clock), every force and tactile device of the graph is a
// simulated one: each other is refused, naming its line and the fix; empty in real time
std::vector<std::string> check_clock(const launch::LaunchDescription& graph);

// check_clock(), then check_params(), then, when it found nothing, every node's own --check
// (launch::check_nodes: files, models, device-dependent parameters): what `enact launch` and
// `enact experiment` do before anything starts
std::vector<std::string> check_graph(const launch::LaunchDescription& graph);

}  // namespace enact::graph
