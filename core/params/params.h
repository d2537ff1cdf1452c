#pragma once
// Node parameters: `--param name=value` from the command line or a launch file, checked
// against the node's declarations (param_table.h) and read with their types and defaults: a
// malformed value or an unknown name is refused with the fix, before the node activates.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/params/param_table.h"
#include "core/math/vec3.h"

namespace enact::graph {

class Params {
 public:
  Params() = default;
  explicit Params(std::string owner) : owner_(std::move(owner)) {}

  // `name=value`; a repeated name keeps the last value
  void set_from(const std::string& name_equals_value);
  void set(const std::string& name, const std::string& value) { values_[name] = value; }

  // declares the parameters of `table` (param_table.h): each of its values given is checked
  // now (type, range, choices; a live-only one given at start is refused), a required one
  // missing too; reads of its names then give its default when none was given. Declaring
  // a table again changes nothing. Throws config::Error naming the parameter and the fix.
  void declare(const ParamTable& table) const;
  // refuses every name given that no declared table holds (a typo: did you mean, and the
  // names known)
  void refuse_unknown() const;

  // given (not defaulted)
  bool has(const std::string& name) const;
  // the value given, else the declared default; reading an undeclared name is a program
  // error (std::logic_error)
  std::string text(const std::string& name) const;
  double number(const std::string& name) const;
  int integer(const std::string& name) const;
  bool flag(const std::string& name) const;
  // "x,y,z"
  math::Vec3 vec3(const std::string& name) const;

  // the params of one component: "sim.scene" -> "scene" for prefix "sim"
  Params scoped(const std::string& prefix) const;

  // every declared parameter (commands left out) with its value in force, in declaration order
  std::vector<std::pair<ParamSpec, std::string>> in_force() const;

 private:
  const std::string& value(const std::string& name) const;
  [[noreturn]] void bad(const std::string& name, const std::string& problem) const;

  std::string owner_;  // node or component, for messages
  std::map<std::string, std::string> values_;
  mutable std::set<std::string> taken_;  // names a component took from these (scoped)
  mutable ParamTable declared_;
};

// the command line of a node: --name N, --param=K=V (or --param K=V), --component=N:PLUGIN,
// --library=PATH (a plugin library of stages, node/loop_component.h), --help, --check;
// anything else is refused
struct NodeArgs {
  std::string name;
  Params params;
  std::vector<std::pair<std::string, std::string>> components;  // name, plugin
  std::vector<std::string> libraries;  // plugin libraries, in order
  bool help = false;
  // check every parameter as the node would before it starts, then exit (0: all good),
  // binding nothing: `enact launch` does this for every node before it starts any
  bool check = false;
};
NodeArgs parse_node_args(int argc, char** argv, const std::string& default_name);

}  // namespace enact::graph
