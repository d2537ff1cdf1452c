#pragma once
// Launch files: a graph of nodes described in YAML, in the spirit of ROS 2's YAML launch
// files (format: docs/launch-files.md). Loading resolves every substitution, include
// and executable, and refuses unknown keys, wrong types and missing executables with
// file:line and the fix, before anything starts.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/rt/clock.h"
#include "core/rt/profile.h"

namespace enact::launch {

struct Param {
  std::string name;
  std::string value;
  std::string source;  // where its value was written: "FILE:LINE", or "--arg NAME=VALUE" ("": unknown)
};

// one component of a real-time container
struct ComponentSpec {
  std::string name;    // instance name, prefixes its params: <name>.<param>
  std::string plugin;  // component class: sim, ffd, tactile (graph::component_kinds())
  std::string library;  // the plugin library that holds it, for a stage of the user's ("": built in)
  std::vector<Param> params;
  int line = 0;
};

// the components of a container that names none, in their order: the simulator, the force
// device and the tactile display, each named as its plugin (graph::component_kinds() says
// what each plugin is)
inline constexpr const char* kDefaultComponents[] = {"sim", "ffd", "tactile"};

// one process of the graph: a node, or a container running several components in one
// real-time thread
struct NodeSpec {
  std::string name;
  std::string exec;        // as written
  std::string path;        // resolved executable
  std::vector<Param> params;
  std::vector<std::string> args;  // extra command-line arguments, before ours
  std::vector<Param> env;
  bool required = false;   // its exit stops the graph (non-zero)
  bool respawn = false;    // restarted after it exits (when not required)
  double respawn_delay_s = 1.0;  // before the first restart; doubled before each next one
  int respawn_max = 3;           // restarts allowed; past them it stays down (said once)
  bool container = false;
  std::vector<ComponentSpec> components;
  std::string source;      // launch file and line, for messages
  int line = 0;

  // the command line: path, args, --name NAME, --component=NAME:PLUGIN..., --param=K=V...
  std::vector<std::string> argv() const;
};

struct ArgSpec {
  std::string name;
  std::string value;        // default, or the value given
  std::string description;
};

struct LaunchDescription {
  std::vector<ArgSpec> args;   // declared by the top file
  std::vector<NodeSpec> nodes; // in start order (includes expanded in place)
  rt::GraphProfile realtime;   // entry `realtime:` (off when there is none)
  rt::GraphClock clock = rt::GraphClock::real;  // entry `clock:` (real when there is none)
  std::string clock_source;    // where the clock was chosen: "FILE:LINE", "--clock" ("": the default)
};

// the graph's clock, chosen on the command line (`--clock`) over the launch file's entry
void choose_clock(LaunchDescription& graph, rt::GraphClock clock);

// finds an executable by name; returns "" when not found
using ExecResolver = std::function<std::string(const std::string& exec)>;

// the default resolver: a path with a '/' as given (relative to the launch file's folder),
// else <enact build>/nodes/<exec>/<exec> next to the running enact binary, else $PATH
ExecResolver default_resolver();

// $(recorded ARG NAME) in a launch file: the recorded simulator's parameter NAME (scene, model,
// rate_hz) in the recording the launch argument ARG names, a file parameter as a copy of the
// recorded file. Reading recordings is not this library's: the program that loads launch
// files gives how (enact: core/replay, recorded_sim_param); none given, the substitution is
// refused. Throws config::Error naming the recording and the fix
using RecordedLookup = std::function<std::string(const std::string& recording, const std::string& name)>;
void set_recorded_lookup(RecordedLookup lookup);

// load a launch file with `--arg name=value` overrides; throws config::Error
LaunchDescription load_launch(const std::string& path, const std::map<std::string, std::string>& args,
                              const ExecResolver& resolve = default_resolver());

}  // namespace enact::launch
