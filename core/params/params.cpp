#include "core/params/params.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "core/config/number.h"
#include "core/config/yaml.h"

namespace enact::graph {

void Params::set_from(const std::string& kv) {
  const std::size_t eq = kv.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw config::Error(owner_ + ": parameter '" + kv + "' is not name=value\n  fix: write --param name=value");
  }
  values_[kv.substr(0, eq)] = kv.substr(eq + 1);
}

void Params::bad(const std::string& name, const std::string& problem) const {
  throw config::Error(owner_ + ": parameter '" + name + "' " + problem);
}

void Params::declare(const ParamTable& table) const {
  for (const ParamSpec& s : table) {
    if (find_spec(declared_, s.name)) continue;
    declared_.push_back(s);
    const auto it = values_.find(s.name);
    if (it == values_.end()) {
      if (s.required) bad(s.name, "is required\n  fix: give it: --param " + s.name + "=... (" + s.doc + ")");
      continue;
    }
    if (!s.at_start) bad(s.name, unknown_problem(table, s.name, owner_));
    if (const auto problem = value_problem(s, it->second)) bad(s.name, *problem);
  }
}

void Params::refuse_unknown() const {
  for (const auto& [k, v] : values_) {
    if (!find_spec(declared_, k) && !taken_.count(k)) bad(k, unknown_problem(declared_, k, owner_.empty() ? "this node" : owner_));
  }
}

bool Params::has(const std::string& name) const { return values_.count(name) > 0; }

const std::string& Params::value(const std::string& name) const {
  const ParamSpec* s = find_spec(declared_, name);
  if (!s) throw std::logic_error(owner_ + ": parameter '" + name + "' is read but not declared");
  const auto it = values_.find(name);
  return it == values_.end() ? s->fallback : it->second;
}

std::string Params::text(const std::string& name) const { return value(name); }

double Params::number(const std::string& name) const {
  const std::string& v = value(name);
  if (v.empty()) return 0.0;
  const auto d = config::parse_number(v);
  if (!d) bad(name, "must be a finite number, got '" + v + "'\n  fix: write e.g. " + name + "=0.01 (SI units)");
  return *d;
}

int Params::integer(const std::string& name) const {
  const double d = number(name);
  if (d != std::floor(d) || std::abs(d) > 1e9) bad(name, "must be a whole number\n  fix: write e.g. " + name + "=4");
  return static_cast<int>(d);
}

bool Params::flag(const std::string& name) const {
  const std::string& v = value(name);
  if (v == "true" || v == "1") return true;
  if (v == "false" || v == "0" || v.empty()) return false;
  bad(name, "must be true or false, got '" + v + "'\n  fix: write " + name + "=true or " + name + "=false");
}

math::Vec3 Params::vec3(const std::string& name) const {
  const std::string& v = value(name);
  double xyz[3];
  std::stringstream ss(v);
  std::string cell;
  for (double& c : xyz) {
    const auto d = std::getline(ss, cell, ',') ? config::parse_number(cell) : std::nullopt;
    if (!d) bad(name, "must be x,y,z, got '" + v + "'\n  fix: write e.g. " + name + "=0,0,0.013 (m)");
    c = *d;
  }
  return {xyz[0], xyz[1], xyz[2]};
}

Params Params::scoped(const std::string& prefix) const {
  Params out(owner_.empty() ? prefix : owner_ + "/" + prefix);
  for (const auto& [k, v] : values_) {
    if (k.rfind(prefix + ".", 0) == 0) {
      out.values_[k.substr(prefix.size() + 1)] = v;
      taken_.insert(k);
    }
  }
  return out;
}

std::vector<std::pair<ParamSpec, std::string>> Params::in_force() const {
  std::vector<std::pair<ParamSpec, std::string>> out;
  for (const ParamSpec& s : declared_) {
    if (s.type == ParamType::command) continue;
    const auto it = values_.find(s.name);
    out.emplace_back(s, it == values_.end() ? s.fallback : it->second);
  }
  return out;
}

NodeArgs parse_node_args(int argc, char** argv, const std::string& default_name) {
  NodeArgs out;
  out.name = default_name;
  std::vector<std::string> params;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const std::string& flag) -> std::string {
      if (a.rfind(flag + "=", 0) == 0) return a.substr(flag.size() + 1);
      if (i + 1 >= argc) throw config::Error(default_name + ": " + flag + " needs a value\n  fix: see --help");
      return argv[++i];
    };
    if (a == "-h" || a == "--help") out.help = true;
    else if (a == "--check") out.check = true;
    else if (a == "--name" || a.rfind("--name=", 0) == 0) out.name = value("--name");
    else if (a == "--param" || a.rfind("--param=", 0) == 0) params.push_back(value("--param"));
    else if (a == "--component" || a.rfind("--component=", 0) == 0) {
      const std::string c = value("--component");
      const std::size_t colon = c.find(':');
      if (colon == std::string::npos) throw config::Error(default_name + ": --component needs NAME:PLUGIN, got '" + c + "'\n  fix: e.g. --component=sim:sim");
      out.components.emplace_back(c.substr(0, colon), c.substr(colon + 1));
    } else if (a == "--library" || a.rfind("--library=", 0) == 0) {
      out.libraries.push_back(value("--library"));
    } else {
      throw config::Error(default_name + ": unknown argument '" + a + "'\n  fix: see --help (parameters are --param name=value)");
    }
  }
  out.params = Params(out.name);
  for (const auto& p : params) out.params.set_from(p);
  return out;
}

}  // namespace enact::graph
