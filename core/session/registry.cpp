#include "core/session/registry.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <thread>

#include "core/config/yaml.h"
#include "core/config/env.h"
#include "core/rt/clock.h"

namespace enact::graph {
namespace {

namespace fs = std::filesystem;

// how often a waiting tool looks at the registry again
constexpr auto kPoll = std::chrono::milliseconds(200);

// a name as a file name: every character but [A-Za-z0-9._-] as %XX ("EXP/s1_CM1" ->
// "EXP%2Fs1_CM1")
std::string file_name(const std::string& name) {
  std::string out;
  for (const unsigned char c : name) {
    if (std::isalnum(c) || c == '.' || c == '_' || c == '-') {
      out += static_cast<char>(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out + ".yaml";
}

std::string now_utc() {
  char s[32];
  const std::time_t t = std::time(nullptr);
  std::strftime(s, sizeof s, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return s;
}

std::string text_of(const GraphEntry& e) {
  std::ostringstream out;
  out << "name: \"" << e.name << "\"\nendpoint: \"" << e.endpoint << "\"\npid: " << e.pid << "\npid_start: " << e.pid_start
      << "\nstarted: \"" << e.started << "\"\nlaunch_file: \"" << e.launch_file << "\"\nfolder: \"" << e.folder << "\"\nloop_cpus: \""
      << e.loop_cpus << "\"\n";
  return out.str();
}

// an entry file, read; nullopt when it is not one (half written, foreign)
std::optional<GraphEntry> read_entry(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  GraphEntry e;
  e.file = file.string();
  while (std::getline(in, line)) {
    const std::size_t colon = line.find(": ");
    if (colon == std::string::npos) continue;
    const std::string key = line.substr(0, colon);
    std::string value = line.substr(colon + 2);
    if (value.size() >= 2 && value.front() == '"' && value.back() == '"') value = value.substr(1, value.size() - 2);
    if (key == "name") e.name = value;
    else if (key == "endpoint") e.endpoint = value;
    else if (key == "pid") e.pid = std::atoll(value.c_str());
    else if (key == "pid_start") e.pid_start = std::atoll(value.c_str());
    else if (key == "started") e.started = value;
    else if (key == "launch_file") e.launch_file = value;
    else if (key == "folder") e.folder = value;
    else if (key == "loop_cpus") e.loop_cpus = value;
  }
  if (e.name.empty() || e.endpoint.empty() || e.pid <= 0) return std::nullopt;
  return e;
}

// removes a stale entry and the folder it names
void remove_stale(const GraphEntry& e) {
  std::error_code ec;
  if (!e.folder.empty()) fs::remove_all(e.folder, ec);
  fs::remove(e.file, ec);
}

std::string names_of(const std::vector<GraphEntry>& graphs) {
  std::string out;
  for (const GraphEntry& g : graphs) out += "\n  " + g.name + "  " + g.endpoint + "  (" + g.launch_file + ", pid " + std::to_string(g.pid) + ")";
  return out;
}

}  // namespace

std::string registry_dir() {
  if (const char* dir = std::getenv(env::kRegistry); dir && *dir) return dir;
  return (fs::temp_directory_path() / ("enact-" + std::to_string(getuid())) / "graphs").string();
}

std::int64_t process_start(std::int64_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(in, stat)) return 0;
  // field 2 (comm) may hold spaces: count from the last ')'
  const std::size_t close = stat.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream rest(stat.substr(close + 2));
  std::string field;
  for (int i = 3; i < 22 && rest >> field; ++i) {
  }
  std::int64_t start = 0;
  rest >> start;
  return start;
}

bool alive(const GraphEntry& e) { return e.pid > 0 && process_start(e.pid) == e.pid_start && e.pid_start != 0; }

std::vector<GraphEntry> list_graphs() {
  std::vector<GraphEntry> out;
  std::error_code ec;
  for (const auto& f : fs::directory_iterator(registry_dir(), ec)) {
    if (f.path().extension() != ".yaml") continue;
    const auto e = read_entry(f.path());
    if (!e) continue;
    if (alive(*e)) out.push_back(*e);
    else remove_stale(*e);
  }
  std::sort(out.begin(), out.end(), [](const GraphEntry& a, const GraphEntry& b) { return a.name < b.name; });
  return out;
}

std::map<int, std::string> running_loops() {
  std::map<int, std::string> loops;
  for (const GraphEntry& g : list_graphs()) {
    std::stringstream cpus(g.loop_cpus);
    for (std::string cpu; std::getline(cpus, cpu, ',');) {
      if (!cpu.empty() && std::isdigit(static_cast<unsigned char>(cpu[0]))) loops[std::atoi(cpu.c_str())] = g.name;
    }
  }
  return loops;
}

void clean_stale_folders() {
  list_graphs();
  std::error_code ec;
  for (const auto& d : fs::directory_iterator(fs::temp_directory_path(), ec)) {
    if (d.path().filename().string().rfind("enact-graph-", 0) != 0) continue;
    struct stat st {};
    if (stat(d.path().c_str(), &st) != 0 || st.st_uid != getuid()) continue;
    GraphEntry owner;
    std::ifstream in(d.path() / "launcher");
    if (!(in >> owner.pid >> owner.pid_start)) continue;
    if (!alive(owner)) fs::remove_all(d.path(), ec);
  }
}

Registration::Registration(const std::string& name, const std::string& endpoint, const std::string& launch_file, const std::string& folder,
                           bool numbered, const std::string& loop_cpus) {
  entry_ = {name, endpoint, getpid(), process_start(getpid()), now_utc(), launch_file, folder, "", loop_cpus};
  const fs::path dir = registry_dir();
  std::error_code ec;
  fs::create_directories(dir, ec);
  for (int n = 1;; ++n) {
    entry_.name = n == 1 ? name : name + "-" + std::to_string(n);
    entry_.file = (dir / file_name(entry_.name)).string();
    // written aside, then linked in place: link() refuses an existing name atomically
    const std::string part = entry_.file + "." + std::to_string(getpid()) + ".part";
    std::ofstream(part) << text_of(entry_);
    bool taken = false;
    for (int attempt = 0; attempt < 2; ++attempt) {
      if (link(part.c_str(), entry_.file.c_str()) == 0) break;
      const auto held = read_entry(entry_.file);
      taken = held && alive(*held);
      if (taken) break;
      if (held) remove_stale(*held);
      else fs::remove(entry_.file, ec);
    }
    fs::remove(part, ec);
    if (!taken) return;
    if (!numbered) {
      throw config::Error("a graph named '" + name + "' runs already (" + read_entry(entry_.file).value_or(GraphEntry{}).endpoint +
                          ")\n  fix: give this one another name (--name NAME), or stop that one");
    }
  }
}

Registration::~Registration() {
  // only our own entry (a stale-entry cleaner may have replaced it after a pid reuse)
  const auto held = read_entry(entry_.file);
  std::error_code ec;
  if (held && held->pid == entry_.pid && held->pid_start == entry_.pid_start) fs::remove(entry_.file, ec);
}

std::optional<GraphEntry> pick_graph(const AttachChoice& choice, const std::vector<GraphEntry>& graphs, const std::string& current) {
  const char* launched_in = std::getenv(env::kAttach);
  const bool named = !choice.graph.empty() || !choice.prefix.empty();
  const std::string endpoint = !choice.endpoint.empty() ? choice.endpoint : !named && launched_in && *launched_in ? launched_in : "";
  std::vector<GraphEntry> fit;
  for (const GraphEntry& g : graphs) {
    const bool match = !endpoint.empty()       ? g.endpoint == endpoint
                       : !choice.graph.empty() ? g.name == choice.graph
                                               : g.name.rfind(choice.prefix, 0) == 0;
    if (!match) continue;
    if (!current.empty() && g.endpoint == current) return g;
    fit.push_back(g);
  }
  // an endpoint needs no entry (another machine's graph)
  if (!endpoint.empty() && fit.empty()) {
    GraphEntry elsewhere;
    elsewhere.name = "(not registered here)";
    elsewhere.endpoint = endpoint;
    return elsewhere;
  }
  if (fit.size() == 1 || (!fit.empty() && (!endpoint.empty() || !choice.prefix.empty()))) return fit.front();
  if (fit.size() > 1) throw AmbiguousGraph("several graphs run; name one with --graph NAME:" + names_of(fit));
  return std::nullopt;
}

GraphEntry find_graph(const AttachChoice& choice, std::ostream& say, const std::function<bool()>& stop) {
  const std::int64_t give_up_ns = rt::now_ns() + static_cast<std::int64_t>(std::max(choice.wait_s, 0.0) * 1e9);
  bool said = false;
  while (true) {
    const std::vector<GraphEntry> graphs = list_graphs();
    if (const std::optional<GraphEntry> g = pick_graph(choice, graphs)) return *g;
    if (!said) {
      said = true;
      const std::string what = !choice.graph.empty() ? "graph '" + choice.graph + "'" : !choice.prefix.empty() ? "a graph named " + choice.prefix + "..." : "a graph";
      say << "waiting for " << what << " to start (enact graph list shows the running ones; Ctrl-C gives up)" << std::endl;
    }
    if ((choice.wait_s >= 0.0 && rt::now_ns() >= give_up_ns) || stop()) {
      throw config::Error(std::string(choice.graph.empty() ? "no graph" : "no graph '" + choice.graph + "'") + " is running" +
                          (graphs.empty() ? "" : "; running:" + names_of(graphs)) + "\n  fix: start one with `enact launch FILE`, or name a running one with --graph NAME");
    }
    std::this_thread::sleep_for(kPoll);
  }
}

std::string attached_line(const GraphEntry& e) { return "attached to graph " + e.name + " at " + e.endpoint; }

}  // namespace enact::graph
