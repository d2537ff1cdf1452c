#include "core/params/param_table.h"

#include <cmath>
#include <sstream>

#include "core/config/number.h"
#include "core/config/suggest.h"

namespace enact::graph {
namespace {

// a bound of a range, as short as it reads
std::string bound(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

std::string joined(const std::vector<std::string>& words, const char* sep) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : sep) + w;
  return out;
}

// an example value of `spec` for a fix
std::string example(const ParamSpec& spec) {
  if (!spec.fallback.empty()) return spec.fallback;
  switch (spec.type) {
    case ParamType::number: return std::isfinite(spec.min) ? bound(spec.min + (spec.above_min ? 1 : 0)) : "0.01";
    case ParamType::integer: return std::isfinite(spec.min) ? bound(spec.min + (spec.above_min ? 1 : 0)) : "1";
    case ParamType::flag: return "true";
    case ParamType::choice: return spec.choices.empty() ? "" : spec.choices.front();
    case ParamType::vec3: return "0,0,0.013";
    case ParamType::text:
    case ParamType::command: return "...";
  }
  return "";
}

std::string refusal(const ParamSpec& spec, const std::string& problem) {
  const std::string unit = unit_of(spec.name);
  return problem + "\n  fix: write e.g. " + spec.name + "=" + example(spec) + (unit.empty() ? "" : " (" + unit + ")");
}

}  // namespace

ParamTable join(std::initializer_list<const ParamTable*> tables) {
  ParamTable out;
  for (const ParamTable* t : tables) out.insert(out.end(), t->begin(), t->end());
  return out;
}

const ParamSpec* find_spec(const ParamTable& table, const std::string& name) {
  for (const ParamSpec& s : table) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

const char* type_name(ParamType type) {
  switch (type) {
    case ParamType::number: return "number";
    case ParamType::integer: return "integer";
    case ParamType::flag: return "flag";
    case ParamType::text: return "text";
    case ParamType::choice: return "choice";
    case ParamType::vec3: return "x,y,z";
    case ParamType::command: return "command";
  }
  return "";
}

std::string range_text(const ParamSpec& spec) {
  if (spec.type == ParamType::choice) return joined(spec.choices, "|");
  if (spec.type == ParamType::flag) return "true|false";
  if (spec.type != ParamType::number && spec.type != ParamType::integer) return "";
  const bool low = std::isfinite(spec.min), high = std::isfinite(spec.max);
  if (low && high) return bound(spec.min) + ".." + bound(spec.max) + (spec.above_min ? " (> " + bound(spec.min) + ")" : "");
  if (low) return (spec.above_min ? "> " : ">= ") + bound(spec.min);
  if (high) return "<= " + bound(spec.max);
  return "";
}

std::optional<std::string> value_problem(const ParamSpec& spec, const std::string& value) {
  const std::string got = ", got '" + value + "'";
  switch (spec.type) {
    case ParamType::number:
    case ParamType::integer: {
      if (value.empty() && spec.fallback.empty()) return std::nullopt;  // not given: the reader decides
      const auto d = config::parse_number(value);
      if (!d) return refusal(spec, "must be a finite number" + got);
      if (spec.type == ParamType::integer && *d != std::floor(*d)) return refusal(spec, "must be a whole number" + got);
      const bool below = spec.above_min ? *d <= spec.min : *d < spec.min;
      if (below || *d > spec.max) return refusal(spec, "is out of range" + got + " (allowed: " + range_text(spec) + ")");
      return std::nullopt;
    }
    case ParamType::flag:
      if (value == "true" || value == "false" || value == "1" || value == "0") return std::nullopt;
      return refusal(spec, "must be true or false" + got);
    case ParamType::choice:
      for (const std::string& c : spec.choices) {
        if (c == value) return std::nullopt;
      }
      return "must be one of " + joined(spec.choices, ", ") + got + config::did_you_mean(value, spec.choices) +
             "\n  fix: write e.g. " + spec.name + "=" + example(spec);
    case ParamType::vec3: {
      if (value.empty() && spec.fallback.empty()) return std::nullopt;  // not given: the reader decides
      std::stringstream ss(value);
      std::string cell;
      int n = 0;
      while (std::getline(ss, cell, ',')) {
        if (!config::parse_number(cell)) n = 99;
        ++n;
      }
      if (n == 3) return std::nullopt;
      return refusal(spec, "must be x,y,z (three numbers)" + got);
    }
    case ParamType::text:
    case ParamType::command: return std::nullopt;
  }
  return std::nullopt;
}

std::string unknown_problem(const ParamTable& table, const std::string& name, const std::string& owner) {
  std::vector<std::string> names;
  for (const ParamSpec& s : table) {
    if (s.at_start) names.push_back(s.name);
  }
  if (const ParamSpec* s = find_spec(table, name); s && !s->at_start) {
    return "is changed only while the graph runs, not at start\n  fix: remove it here; once running: enact param set " + owner + "." + name + " VALUE";
  }
  return "is not a parameter of " + owner + config::did_you_mean(name, names) + "\n  fix: use one of: " + joined(names, ", ");
}

std::string help_lines(const ParamTable& table, const std::string& prefix) {
  std::string out;
  for (const ParamSpec& s : table) {
    std::string head = "  " + prefix + s.name;
    if (!s.at_start) head += s.type == ParamType::command ? " (command)" : "";
    else if (s.required) head += " (required)";
    else head += "=" + s.fallback;
    const std::string range = range_text(s);
    std::string doc = s.doc + (range.empty() || s.type == ParamType::flag ? "" : " [" + range + "]");
    if (s.live) doc += s.at_start ? " (live)" : " (live only: enact param set)";
    out += head + (head.size() < 30 ? std::string(30 - head.size(), ' ') : "  ") + doc + "\n";
  }
  return out;
}

}  // namespace enact::graph
