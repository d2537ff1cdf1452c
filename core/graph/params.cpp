#include "core/graph/params.h"

#include <unistd.h>

#include <climits>
#include <cmath>
#include <cstdlib>
#include <sstream>

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

const std::string* Params::find(const std::string& name) const {
  read_.insert(name);
  const auto it = values_.find(name);
  return it == values_.end() ? nullptr : &it->second;
}

void Params::bad(const std::string& name, const std::string& problem, const std::string& fix) const {
  throw config::Error(owner_ + ": parameter '" + name + "' " + problem + "\n  fix: " + fix);
}

bool Params::has(const std::string& name) const { return find(name) != nullptr; }

std::string Params::text(const std::string& name, const std::string& fallback) const {
  const std::string* v = find(name);
  return v ? *v : fallback;
}

double Params::number(const std::string& name, double fallback) const {
  const std::string* v = find(name);
  if (!v) return fallback;
  const auto d = config::parse_number(*v);
  if (!d) bad(name, "must be a finite number, got '" + *v + "'", "write e.g. " + name + "=0.01 (SI units)");
  return *d;
}

int Params::integer(const std::string& name, int fallback) const {
  const double d = number(name, fallback);
  if (d != std::floor(d) || std::abs(d) > 1e9) bad(name, "must be a whole number", "write e.g. " + name + "=4");
  return static_cast<int>(d);
}

bool Params::flag(const std::string& name, bool fallback) const {
  const std::string* v = find(name);
  if (!v) return fallback;
  if (*v == "true" || *v == "1") return true;
  if (*v == "false" || *v == "0") return false;
  bad(name, "must be true or false, got '" + *v + "'", "write " + name + "=true or " + name + "=false");
}

physics::Vec3 Params::vec3(const std::string& name, const physics::Vec3& fallback) const {
  const std::string* v = find(name);
  if (!v) return fallback;
  double xyz[3];
  std::stringstream ss(*v);
  std::string cell;
  for (double& c : xyz) {
    const auto d = std::getline(ss, cell, ',') ? config::parse_number(cell) : std::nullopt;
    if (!d) bad(name, "must be x,y,z, got '" + *v + "'", "write e.g. " + name + "=0,0,0.013 (m)");
    c = *d;
  }
  return {xyz[0], xyz[1], xyz[2]};
}

Params Params::scoped(const std::string& prefix) const {
  Params out(owner_.empty() ? prefix : owner_ + "/" + prefix);
  for (const auto& [k, v] : values_) {
    if (k.rfind(prefix + ".", 0) == 0) {
      out.values_[k.substr(prefix.size() + 1)] = v;
      read_.insert(k);
    }
  }
  return out;
}

void Params::refuse_unread(const std::vector<std::string>& known) const {
  for (const auto& [k, v] : values_) {
    if (read_.count(k)) continue;
    std::string list;
    for (const auto& n : known) list += (list.empty() ? "" : ", ") + n;
    bad(k, "is not a parameter of " + (owner_.empty() ? std::string("this node") : owner_), "use one of: " + list);
  }
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
    } else {
      throw config::Error(default_name + ": unknown argument '" + a + "'\n  fix: see --help (parameters are --param name=value)");
    }
  }
  out.params = Params(out.name);
  for (const auto& p : params) out.params.set_from(p);
  return out;
}

void report_ready() {
  const char* fd = std::getenv("ENACT_READY_FD");
  if (!fd) return;
  const auto n = config::parse_integer(fd);
  if (!n || *n < 0 || *n > INT_MAX || write(static_cast<int>(*n), "ready\n", 6) != 6) return;
  close(static_cast<int>(*n));
}

}  // namespace enact::graph
