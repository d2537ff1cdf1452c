#include "core/launch/launch_file.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "core/config/share.h"
#include "core/config/yaml.h"

namespace enact::launch {
namespace {

namespace fs = std::filesystem;
using config::Map;

// one launch file being read: its path and its arguments
struct Scope {
  std::string file;
  std::map<std::string, std::string> vars;
  std::set<std::string> from_cli;  // the vars given by --arg (the top file's)
};

// where a value was written: FILE:LINE, or the --arg it substitutes
std::string source_of(const Scope& scope, const YAML::Node& at) {
  const std::string line = scope.file + ":" + std::to_string(at.Mark().line + 1);
  const std::string raw = at.IsScalar() ? at.Scalar() : "";
  for (const std::string& name : scope.from_cli) {
    if (raw.find("$(var " + name + ")") != std::string::npos) return "--arg " + name + "=" + scope.vars.at(name) + " (" + line + ")";
  }
  return line;
}

RecordedLookup& recorded_lookup() {
  static RecordedLookup lookup;
  return lookup;
}

// $(var NAME), $(env NAME [DEFAULT]), $(dirname), $(share) and $(recorded ARG NAME) in a scalar
std::string substitute(const Scope& scope, const YAML::Node& at, const std::string& text) {
  std::string out;
  std::size_t pos = 0;
  while (true) {
    const std::size_t open = text.find("$(", pos);
    if (open == std::string::npos) return out + text.substr(pos);
    const std::size_t close = text.find(')', open);
    if (close == std::string::npos) config::fail(scope.file, at, "unclosed substitution in '" + text + "'", "write $(var NAME), $(env NAME), $(dirname), $(share) or $(recorded ARG NAME)");
    out += text.substr(pos, open - pos);
    std::string expr = text.substr(open + 2, close - open - 2);
    const std::size_t space = expr.find(' ');
    const std::string kind = expr.substr(0, space);
    const std::string rest = space == std::string::npos ? "" : expr.substr(space + 1);
    if (kind == "dirname") {
      out += fs::absolute(scope.file).parent_path().string();
    } else if (kind == "share") {
      // enact's shipped files: <prefix>/share/enact, or the source tree of a build (config/share.h)
      try {
        out += config::share_dir();
      } catch (const config::Error& e) {
        throw config::Error(scope.file + ":" + std::to_string(at.Mark().line + 1) + ": " + e.what());
      }
    } else if (kind == "recorded") {
      // the recorded simulator's parameter, from the recording a launch argument names
      const std::size_t sep = rest.find(' ');
      const std::string arg = rest.substr(0, sep), name = sep == std::string::npos ? "" : rest.substr(sep + 1);
      const auto it = scope.vars.find(arg);
      if (it == scope.vars.end() || name.empty()) {
        config::fail(scope.file, at, "'$(" + expr + ")' names no launch argument and parameter", "write $(recorded ARG NAME), ARG a launch argument declared before it (the recording), NAME the simulator's parameter (scene, model, rate_hz)");
      }
      if (!recorded_lookup()) config::fail(scope.file, at, "$(recorded ...) needs a program that reads recordings", "run the file with enact launch");
      try {
        out += recorded_lookup()(it->second, name);
      } catch (const config::Error& e) {
        throw config::Error(scope.file + ":" + std::to_string(at.Mark().line + 1) + ": " + e.what());
      }
    } else if (kind == "var") {
      const auto it = scope.vars.find(rest);
      if (it == scope.vars.end()) config::fail(scope.file, at, "unknown launch argument '" + rest + "'", "declare it first: - arg: {name: " + rest + ", default: ...}");
      out += it->second;
    } else if (kind == "env") {
      const std::size_t sep = rest.find(' ');
      const std::string name = rest.substr(0, sep);
      const char* value = std::getenv(name.c_str());
      if (!value && sep == std::string::npos) config::fail(scope.file, at, "environment variable '" + name + "' is not set", "set it, or give a default: $(env " + name + " DEFAULT)");
      out += value ? value : rest.substr(sep + 1);
    } else {
      config::fail(scope.file, at, "unknown substitution '$(" + expr + ")'", "use $(var NAME), $(env NAME [DEFAULT]), $(dirname), $(share) or $(recorded ARG NAME)");
    }
    pos = close + 1;
  }
}

std::string scalar(const Scope& scope, const YAML::Node& n, const std::string& what) {
  if (!n.IsScalar()) config::fail(scope.file, n, what + " must be a single value", "write a string or a number");
  return substitute(scope, n, n.Scalar());
}

// `[{name: N, value: V}, ...]`
std::vector<Param> pairs(const Scope& scope, const Map& m, const char* key) {
  std::vector<Param> out;
  for (const auto& n : m.list(key)) {
    const Map p(n, scope.file, key, {"name", "value"});
    out.push_back({p.text("name"), scalar(scope, p.get("value"), std::string(key) + " value"), source_of(scope, p.get("value"))});
  }
  return out;
}

// a YAML file of `name: value` lines
std::vector<Param> param_file(const Scope& scope, const Map& m) {
  const std::string path = scalar(scope, m.get("param_file"), "param_file");
  const fs::path full = config::find_file(path, scope.file);
  const YAML::Node root = config::load_file(full.string());
  std::vector<Param> out;
  for (const auto& kv : root) {
    if (!kv.second.IsScalar()) config::fail(full.string(), kv.second, "parameter '" + kv.first.Scalar() + "' must be a single value", "write name: value");
    out.push_back({kv.first.Scalar(), kv.second.Scalar(), full.string() + ":" + std::to_string(kv.second.Mark().line + 1)});
  }
  return out;
}

// params of a node or component: param_file first, then param entries (which override)
std::vector<Param> params(const Scope& scope, const Map& m) {
  std::vector<Param> out = m.has("param_file") ? param_file(scope, m) : std::vector<Param>{};
  for (const Param& p : pairs(scope, m, "param")) {
    bool replaced = false;
    for (Param& q : out) {
      if (q.name == p.name) {
        q = p;
        replaced = true;
      }
    }
    if (!replaced) out.push_back(p);
  }
  return out;
}

bool flag(const Scope& scope, const Map& m, const char* key, bool fallback) {
  if (!m.has(key)) return fallback;
  const std::string v = scalar(scope, m.get(key), key);
  if (v == "true" || v == "True") return true;
  if (v == "false" || v == "False") return false;
  m.fail(key, std::string(key) + " must be true or false, got '" + v + "'", "write true or false");
}

struct Loader {
  ExecResolver resolve;
  LaunchDescription out;
  std::set<std::string> names;
  std::vector<std::string> stack;  // the files being read, outermost first
  std::string realtime_at;  // file:line of the realtime: entry, once read

  void executable(const Scope& scope, const Map& m, NodeSpec& n, const std::string& fallback) {
    n.exec = m.has("exec") ? scalar(scope, m.get("exec"), "exec") : fallback;
    std::string exec = n.exec;
    if (exec.find('/') != std::string::npos && !fs::path(exec).is_absolute()) exec = (fs::absolute(scope.file).parent_path() / exec).lexically_normal().string();
    n.path = resolve(exec);
    if (n.path.empty()) m.fail("exec", "executable '" + n.exec + "' not found", "build it (scripts/build.sh), or give its path");
  }

  void common(const Scope& scope, const Map& m, NodeSpec& n) {
    n.name = scalar(scope, m.get("name"), "name");
    if (n.name.empty() || n.name.find_first_of(" /:=") != std::string::npos) m.fail("name", "node name '" + n.name + "' is not a plain word", "use letters, digits, '_' or '-'");
    if (!names.insert(n.name).second) m.fail("name", "two nodes are named '" + n.name + "'", "give every node its own name");
    n.source = scope.file + ":" + std::to_string(m.line());
    n.line = m.line();
    n.required = flag(scope, m, "required", false);
    n.respawn = flag(scope, m, "respawn", false);
    if (n.required && n.respawn) m.fail("respawn", "node '" + n.name + "' is both required and respawned", "choose one: a required node's exit stops the graph");
    if (m.has("respawn_delay")) n.respawn_delay_s = m.positive("respawn_delay", 1.0, true);
    if (m.has("respawn_max")) n.respawn_max = m.integer("respawn_max", 3, 0, 1000);
    n.env = pairs(scope, m, "env");
    if (m.has("args")) {
      const YAML::Node a = m.get("args");
      if (a.IsScalar()) {
        std::string word;
        for (char c : scalar(scope, a, "args") + " ") {
          if (c != ' ') word += c;
          else if (!word.empty()) n.args.push_back(std::exchange(word, ""));
        }
      } else {
        for (const auto& item : a) n.args.push_back(scalar(scope, item, "args entry"));
      }
    }
  }

  // a component list (component: [{name, plugin, library, param, param_file}, ...])
  std::vector<ComponentSpec> components(const Scope& scope, const Map& m) {
    std::vector<ComponentSpec> list;
    std::set<std::string> names;
    for (const auto& c : m.list("component")) {
      const Map cm(c, scope.file, "component", {"name", "plugin", "library", "param", "param_file"});
      ComponentSpec spec{scalar(scope, cm.get("name"), "name"), scalar(scope, cm.get("plugin"), "plugin"),
                         cm.has("library") ? scalar(scope, cm.get("library"), "library") : "", params(scope, cm), cm.line()};
      if (!names.insert(spec.name).second) cm.fail("name", "two components are named '" + spec.name + "'", "give every component its own name");
      list.push_back(spec);
    }
    return list;
  }

  // a node; enact-sim's may list stages of a user's (component:), which run in its answer
  void node(const Scope& scope, const YAML::Node& y) {
    const Map m(y, scope.file, "node", {"name", "exec", "param", "param_file", "component", "args", "env", "required", "respawn", "respawn_delay", "respawn_max"});
    NodeSpec n;
    common(scope, m, n);
    executable(scope, m, n, "");
    n.params = params(scope, m);
    n.components = components(scope, m);
    out.nodes.push_back(n);
  }

  void container(const Scope& scope, const YAML::Node& y) {
    const Map m(y, scope.file, "container", {"name", "exec", "param", "param_file", "component", "args", "env", "required", "respawn", "respawn_delay", "respawn_max"});
    NodeSpec n;
    common(scope, m, n);
    executable(scope, m, n, "enact-rt");
    n.params = params(scope, m);
    n.container = true;
    n.components = components(scope, m);
    // none named: the default three, their parameters given as the container's (sim.scene, ...)
    if (!m.has("component")) {
      for (const char* plugin : kDefaultComponents) n.components.push_back({plugin, plugin, "", {}, m.line()});
    }
    if (n.components.empty()) m.fail("component", "container '" + n.name + "' has an empty component list", "list its components (component: [{name: sim, plugin: sim}, ...]), or leave component: out for sim, ffd and tactile");
    out.nodes.push_back(n);
  }

  // the real-time profile: `realtime: {loop: [ffd, sim], fifo_priority: 0, cpu_latency: true}`
  void realtime(const Scope& scope, const YAML::Node& y) {
    const Map m(y, scope.file, "realtime", {"enabled", "loop", "fifo_priority", "cpu_latency"});
    const std::string at = scope.file + ":" + std::to_string(m.line());
    if (!realtime_at.empty()) m.fail("loop", "a second realtime: entry (the first is at " + realtime_at + ")", "keep one realtime: entry per graph");
    rt::GraphProfile& g = out.realtime;
    g.enabled = flag(scope, m, "enabled", true);
    g.cpu_latency = flag(scope, m, "cpu_latency", true);
    for (const auto& n : m.list("loop")) g.loop.push_back(scalar(scope, n, "loop entry"));
    if (m.has("fifo_priority")) {
      const std::string text = scalar(scope, m.get("fifo_priority"), "fifo_priority");
      std::size_t used = 0;
      try {
        g.fifo_priority = std::stoi(text, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != text.size()) m.fail("fifo_priority", "fifo_priority '" + text + "' is not a whole number", "write 0 (normal scheduling) or a priority, e.g. 80");
    }
    try {
      g.validate();
    } catch (const config::Error& e) {
      throw config::Error(at + ": " + e.what());
    }
    realtime_at = at;
  }

  // the graph clock: `clock: simulated` (or real)
  void clock(const Scope& scope, const YAML::Node& y) {
    const std::string at = source_of(scope, y);
    if (!out.clock_source.empty()) config::fail(scope.file, y, "a second clock: entry (the first is at " + out.clock_source + ")", "keep one clock: entry per graph");
    const std::string text = scalar(scope, y, "clock");
    const auto parsed = rt::parse_clock(text);
    if (!parsed) config::fail(scope.file, y, "clock must be real or simulated, got '" + text + "'", "write clock: real (the deadlines of rate_hz) or clock: simulated (as fast as the machine goes)");
    out.clock = *parsed;
    out.clock_source = at;
  }

  // every loop process of the profile is a node of the graph
  void check_realtime() const {
    if (realtime_at.empty()) return;
    for (const std::string& name : out.realtime.loop) {
      if (!names.count(name)) {
        throw config::Error(realtime_at + ": realtime loop names '" + name + "', which is no node of the graph\n  fix: list the nodes of the zero-delay loop, e.g. loop: [ffd, sim]");
      }
    }
  }

  void include(const Scope& scope, const YAML::Node& y) {
    const Map m(y, scope.file, "include", {"file", "arg"});
    const std::string file = scalar(scope, m.get("file"), "file");
    const std::string path = fs::absolute(config::find_file(file, scope.file)).lexically_normal().string();
    for (const std::string& open : stack) {
      if (open == path) m.fail("file", "include cycle: " + path + " includes itself (directly or through others)", "remove the include that leads back to it");
    }
    std::map<std::string, std::string> args;
    for (const Param& p : pairs(scope, m, "arg")) args[p.name] = p.value;
    file_(path, args, false);
  }

  // one launch file; `top`: its declared args are the ones --arg may set
  void file_(const std::string& path, const std::map<std::string, std::string>& given, bool top) {
    stack.push_back(fs::absolute(path).lexically_normal().string());
    const YAML::Node root = config::load_file(path);
    const Map doc(root, path, "launch file", {"launch", "description"});
    Scope scope{path, {}, {}};
    std::set<std::string> declared;
    const std::vector<YAML::Node> actions = doc.list("launch");
    for (const auto& action : actions) {
      if (!action.IsMap() || action.size() != 1) config::fail(path, action, "each launch entry is one of arg:, node:, container:, include:, realtime:, clock:", "write e.g. - node: {name: sim, exec: enact-sim}");
      const std::string kind = action.begin()->first.Scalar();
      const YAML::Node body = action.begin()->second;
      if (kind == "arg") {
        const Map a(body, path, "arg", {"name", "default", "description"});
        const std::string name = a.text("name");
        declared.insert(name);
        const auto it = given.find(name);
        if (it == given.end() && !a.has("default")) a.fail("name", "launch argument '" + name + "' has no default and was not given", "give it: --arg " + name + "=VALUE, or add default:");
        const std::string value = it != given.end() ? it->second : scalar(scope, a.get("default"), "default");
        scope.vars[name] = value;
        if (top && it != given.end()) scope.from_cli.insert(name);
        if (top) out.args.push_back({name, value, a.text("description", "")});
      } else if (kind == "node") {
        node(scope, body);
      } else if (kind == "container") {
        container(scope, body);
      } else if (kind == "include") {
        include(scope, body);
      } else if (kind == "realtime") {
        realtime(scope, body);
      } else if (kind == "clock") {
        clock(scope, body);
      } else {
        config::fail(path, action.begin()->first, "unknown launch entry '" + kind + "'", "use arg, node, container, include, realtime or clock");
      }
    }
    for (const auto& [name, value] : given) {
      if (!declared.count(name)) {
        std::string list;
        for (const auto& d : declared) list += (list.empty() ? "" : ", ") + d;
        throw config::Error(path + ": unknown launch argument '" + name + "'\n  fix: declare it in the file, or use one of: " + (list.empty() ? "(none)" : list));
      }
    }
    stack.pop_back();
  }
};

}  // namespace

std::vector<std::string> NodeSpec::argv() const {
  std::vector<std::string> v{path};
  v.insert(v.end(), args.begin(), args.end());
  v.push_back("--name");
  v.push_back(name);
  std::vector<std::string> libraries;
  for (const ComponentSpec& c : components) {
    if (!c.library.empty() && std::find(libraries.begin(), libraries.end(), c.library) == libraries.end()) libraries.push_back(c.library);
  }
  for (const std::string& l : libraries) v.push_back("--library=" + l);
  for (const ComponentSpec& c : components) v.push_back("--component=" + c.name + ":" + c.plugin);
  for (const Param& p : params) v.push_back("--param=" + p.name + "=" + p.value);
  for (const ComponentSpec& c : components) {
    for (const Param& p : c.params) v.push_back("--param=" + c.name + "." + p.name + "=" + p.value);
  }
  return v;
}

void choose_clock(LaunchDescription& graph, rt::GraphClock clock) {
  graph.clock = clock;
  graph.clock_source = "--clock";
}

void set_recorded_lookup(RecordedLookup lookup) { recorded_lookup() = std::move(lookup); }

ExecResolver default_resolver() {
  return [](const std::string& exec) -> std::string {
    std::error_code ec;
    auto runnable = [&](const fs::path& p) { return fs::is_regular_file(p, ec) && access(p.c_str(), X_OK) == 0; };
    if (exec.find('/') != std::string::npos) return runnable(exec) ? exec : "";
    // next to the running binary: <build>/nodes/enact/enact -> <build>/nodes/<exec>/<exec>
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      const fs::path sibling = self.parent_path().parent_path() / exec / exec;
      if (runnable(sibling)) return sibling.string();
      if (runnable(self.parent_path() / exec)) return (self.parent_path() / exec).string();
    }
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= dirs.size()) {
      const std::size_t end = dirs.find(':', start);
      const fs::path candidate = fs::path(dirs.substr(start, end - start)) / exec;
      if (runnable(candidate)) return candidate.string();
      if (end == std::string::npos) break;
      start = end + 1;
    }
    return "";
  };
}

LaunchDescription load_launch(const std::string& path, const std::map<std::string, std::string>& args, const ExecResolver& resolve) {
  Loader loader{resolve, {}, {}, {}, {}};
  loader.file_(config::find_file(path), args, true);
  loader.check_realtime();
  if (loader.out.nodes.empty()) throw config::Error(path + ": the launch file starts no node\n  fix: add - node: or - container: entries");
  return loader.out;
}

}  // namespace enact::launch
