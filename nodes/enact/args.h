#pragma once
// A small command-line parser: positionals, --name value, --name=value and flags.
// Unknown options and missing values are errors that name the option.
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/config/lists.h"
#include "core/config/share.h"
#include "core/rt/clock.h"

namespace enact::cli {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;
  std::set<std::string> flags;

  bool flag(const std::string& name) const { return flags.count(name) != 0; }
  bool has(const std::string& name) const { return options.count(name) != 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  double number(const std::string& name, double fallback) const;
};

// `valued`: options that take a value; `switches`: flags; -h/--help is always a flag
Args parse(int argc, char** argv, int first, const std::set<std::string>& valued, const std::set<std::string>& switches);

// the items of a comma-separated list ("CM0,CM1"), empty items left out
using config::split_commas;

// "NAME a b c" up to the next option: the items (UsageError if none), removed from argv
// (argc shrinks); empty when NAME is absent
std::vector<std::string> take_list(int& argc, char** argv, const std::string& name);

// the values of a repeatable option "NAME VALUE" (or "NAME=VALUE"), in order, removed from
// argv (argc shrinks); UsageError when one has no value
std::vector<std::string> take_repeated(int& argc, char** argv, const std::string& name);

// --clock real|simulated, when given (UsageError for another value)
std::optional<rt::GraphClock> clock_option(const Args& a);

// a file as given, else in enact's share (the installed <prefix>/share/enact, or the source tree
// of a build): `enact launch launch/bridge_rt.yaml` finds launch/... from anywhere
// (core/config/share.h); config::Error listing where it looked when none has it
using config::find_file;

// a duration as m:ss, or h:mm:ss from an hour (progress lines)
std::string clock_text(double s);

}  // namespace enact::cli
