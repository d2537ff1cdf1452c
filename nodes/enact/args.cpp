#include "nodes/enact/args.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/config/number.h"
#include "core/config/suggest.h"

namespace enact::cli {

std::string Args::get(const std::string& name, const std::string& fallback) const {
  const auto it = options.find(name);
  return it == options.end() ? fallback : it->second;
}

double Args::number(const std::string& name, double fallback) const {
  if (!has(name)) return fallback;
  const std::string text = get(name);
  const auto v = config::parse_number(text);
  if (!v) throw UsageError("--" + name + " needs a number, got '" + text + "'");
  return *v;
}

Args parse(int argc, char** argv, int first, const std::set<std::string>& valued, const std::set<std::string>& switches) {
  Args a;
  for (int i = first; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      a.flags.insert("help");
      continue;
    }
    if (arg == "-o") arg = "--out";
    if (arg.rfind("--", 0) != 0 || arg.size() == 2) {
      a.positional.push_back(arg);
      continue;
    }
    std::string name = arg.substr(2);
    std::string value;
    const auto eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (switches.count(name) && !inline_value) {
      a.flags.insert(name);
    } else if (valued.count(name)) {
      if (!inline_value) {
        if (i + 1 >= argc) throw UsageError("--" + name + " needs a value");
        value = argv[++i];
      }
      a.options[name] = value;
    } else {
      std::vector<std::string> known(valued.begin(), valued.end());
      known.insert(known.end(), switches.begin(), switches.end());
      throw UsageError("unknown option --" + name + config::did_you_mean(name, known, "--"));
    }
  }
  return a;
}

std::vector<std::string> take_list(int& argc, char** argv, const std::string& name) {
  std::vector<std::string> out;
  int kept = 0;
  for (int i = 0; i < argc; ++i) {
    if (argv[i] == name) {
      while (i + 1 < argc && argv[i + 1][0] != '-') out.emplace_back(argv[++i]);
      if (out.empty()) throw UsageError(name + " needs at least one value");
      continue;
    }
    argv[kept++] = argv[i];
  }
  argc = kept;
  return out;
}

std::vector<std::string> take_repeated(int& argc, char** argv, const std::string& name) {
  std::vector<std::string> out;
  int kept = 0;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.starts_with(name + "=")) {
      out.push_back(arg.substr(name.size() + 1));
    } else if (arg == name) {
      if (i + 1 >= argc) throw UsageError(name + " needs a value");
      out.emplace_back(argv[++i]);
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  return out;
}

std::string clock_text(double s) {
  const long total = static_cast<long>(s + 0.5);
  char buf[32];
  if (total >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", total / 3600, total / 60 % 60, total % 60);
  else std::snprintf(buf, sizeof buf, "%ld:%02ld", total / 60, total % 60);
  return buf;
}

std::optional<rt::GraphClock> clock_option(const Args& a) {
  if (!a.has("clock")) return std::nullopt;
  const auto clock = rt::parse_clock(a.get("clock"));
  if (!clock) throw UsageError("--clock must be real or simulated, got '" + a.get("clock") + "'");
  return clock;
}

}  // namespace enact::cli
