#pragma once
// The declaration of a node's or component's parameters, each once: its name (with its unit),
// type, default, range or choices, one line of doc, and whether it may change while the graph
// runs. A node's --help, its refusal of unknown names and bad values (with the fix), the
// check of a launch file before anything starts, and `enact param list/get/dump/load` all
// read these tables (core/params/node_params.h holds every node's).
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/config/number.h"

namespace enact::graph {

enum class ParamType : std::uint8_t {
  number,   // a finite number, in the unit of its name
  integer,  // a whole number
  flag,     // true or false
  text,     // any text (a name, a file, an endpoint)
  choice,   // one of `choices`
  vec3,     // x,y,z
  command,  // live only, no value kept: an action (reset)
};

struct ParamSpec {
  std::string name;             // with its unit: rate_hz, start_m, stiffness_n_per_m
  ParamType type = ParamType::number;
  std::string fallback;         // the default, as written on a command line ("": none)
  double min = -std::numeric_limits<double>::infinity();  // number, integer: inclusive
  double max = std::numeric_limits<double>::infinity();
  bool above_min = false;       // min itself is excluded (> min)
  std::vector<std::string> choices;  // choice (a value outside them is refused)
  std::string doc;              // one line
  bool live = false;            // may change while the graph runs (enact param set)
  bool at_start = true;         // may be given at start (--param, a launch file); false: live only
  bool required = false;        // must be given at start
};

using ParamTable = std::vector<ParamSpec>;

// the tables one after the other (a node's own parameters and its component's)
ParamTable join(std::initializer_list<const ParamTable*> tables);

// the declaration named `name` in `table` (nullptr: none)
const ParamSpec* find_spec(const ParamTable& table, const std::string& name);

// the unit its name ends with ("Hz" for rate_hz, "N/m" for stiffness_n_per_m; "" for none)
using config::unit_of;

// its type as a word (number, integer, flag, text, choice, x,y,z, command)
const char* type_name(ParamType type);

// what values it takes, for listings: "1..44000", "> 0", ">= 0", "sample|hold", "true|false"; "" for any
std::string range_text(const ParamSpec& spec);

// why `value` is not a value of `spec` and the fix ("must be ...\n  fix: ..."); nullopt when
// it is one
std::optional<std::string> value_problem(const ParamSpec& spec, const std::string& value);

// the refusal of an unknown name `name`: "is not a parameter of OWNER (did you mean X?)\n
// fix: use one of ..." (names at start only when `at_start`)
std::string unknown_problem(const ParamTable& table, const std::string& name, const std::string& owner);

// the --help lines of `table`, each "  NAME=DEFAULT  doc [range] (live)", names after `prefix`
std::string help_lines(const ParamTable& table, const std::string& prefix = "");

}  // namespace enact::graph
