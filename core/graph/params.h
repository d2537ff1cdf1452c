#pragma once
// Node parameters: `--param name=value` from the command line or a launch file, read with
// types and checked: a malformed value or an unknown name is refused with the fix, before
// the node activates.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/physics/vec3.h"

namespace enact::graph {

class Params {
 public:
  Params() = default;
  explicit Params(std::string owner) : owner_(std::move(owner)) {}

  // `name=value`; a repeated name keeps the last value
  void set_from(const std::string& name_equals_value);
  void set(const std::string& name, const std::string& value) { values_[name] = value; }

  bool has(const std::string& name) const;
  std::string text(const std::string& name, const std::string& fallback) const;
  double number(const std::string& name, double fallback) const;
  int integer(const std::string& name, int fallback) const;
  bool flag(const std::string& name, bool fallback) const;
  // "x,y,z"
  physics::Vec3 vec3(const std::string& name, const physics::Vec3& fallback) const;

  // the params of one component: "sim.scene" -> "scene" for prefix "sim"
  Params scoped(const std::string& prefix) const;
  // refuse every param that no reader asked for (a typo), listing the known ones
  void refuse_unread(const std::vector<std::string>& known) const;

 private:
  const std::string* find(const std::string& name) const;
  [[noreturn]] void bad(const std::string& name, const std::string& problem, const std::string& fix) const;

  std::string owner_;  // node or component, for messages
  std::map<std::string, std::string> values_;
  mutable std::set<std::string> read_;
};

// the command line of a node: --name N, --param=K=V (or --param K=V), --component=N:PLUGIN,
// --help, --check; anything else is refused
struct NodeArgs {
  std::string name;
  Params params;
  std::vector<std::pair<std::string, std::string>> components;  // name, plugin
  bool help = false;
  // check every parameter as the node would before it starts, then exit (0: all good),
  // binding nothing: `enact launch` does this for every node before it starts any
  bool check = false;
};
NodeArgs parse_node_args(int argc, char** argv, const std::string& default_name);

// tell the launcher this node is active (ENACT_READY_FD), if started by one
void report_ready();

}  // namespace enact::graph
