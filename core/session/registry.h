#pragma once
// The per-user registry of running graphs (docs/concepts.md, "Graphs by name"): one small file per
// running graph in /tmp/enact-<uid>/graphs/, written by the process that runs it (enact
// launch, an experiment's trial, enact play) and removed when it ends. An entry whose
// process is gone (kill -9) is stale: listing the registry removes it, and the temporary
// folder it names. Tools attach by name (--graph NAME) and never guess between several.
//
// An entry is "key: value" lines (YAML; scripts/attach_example.py reads it too):
//   name: bridge_rt
//   endpoint: tcp://127.0.0.1:40123
//   pid: 4242
//   pid_start: 123456        (the process's start time, /proc/PID/stat field 22)
//   started: 2026-11-24T07:10:00Z
//   launch_file: launch/bridge_rt.yaml
//   folder: /tmp/enact-graph-AbC123
//   loop_cpus: "1"           (the CPUs its real-time loop is pinned to; "": none)
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace enact::graph {

struct GraphEntry {
  std::string name;
  std::string endpoint;       // the attach point
  std::int64_t pid = 0;       // the process running the graph
  std::int64_t pid_start = 0; // its start time in clock ticks since boot (tells a reused pid)
  std::string started;        // UTC, ISO 8601
  std::string launch_file;
  std::string folder;         // the graph's temporary folder (removed with a stale entry)
  std::string file;           // the entry's own file
  std::string loop_cpus;      // the CPUs its loop is pinned to ("1", "": none)
};

// the loops of the graphs running now, for placing another: CPU -> graph name
std::map<int, std::string> running_loops();

// the registry's folder: /tmp/enact-<uid>/graphs ($ENACT_REGISTRY overrides it)
std::string registry_dir();

// the start time of process `pid` (clock ticks since boot), 0 when there is no such process
std::int64_t process_start(std::int64_t pid);

// true while the entry's process runs (same pid, same start time)
bool alive(const GraphEntry& e);

// the running graphs, by name; stale entries (and their folders) are removed on the way
std::vector<GraphEntry> list_graphs();

// removes the temporary folders of graphs whose process is gone (kill -9 of a launcher)
void clean_stale_folders();

// this process's entry while it lives: registered at construction, removed at destruction
class Registration {
 public:
  // registers graph `name` for this process. A running graph of that name: with `numbered`,
  // the first free of NAME-2, NAME-3, ... is taken instead; else config::Error (the fix:
  // another --name).
  Registration(const std::string& name, const std::string& endpoint, const std::string& launch_file, const std::string& folder,
               bool numbered = false, const std::string& loop_cpus = "");
  ~Registration();
  Registration(const Registration&) = delete;
  Registration& operator=(const Registration&) = delete;

  const GraphEntry& entry() const { return entry_; }

 private:
  GraphEntry entry_;
};

// which graph a tool attaches to
struct AttachChoice {
  std::string graph;     // --graph NAME ("" : not given)
  std::string endpoint;  // --attach ENDPOINT ("" : not given)
  double wait_s = -1.0;  // how long to wait for a graph to appear (< 0: until stopped)
  // a name prefix: the first graph whose name starts with it (an experiment's trials)
  std::string prefix;
};

// several graphs run and the tool was not told which (exit 2)
struct AmbiguousGraph : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The one rule by which every tool, observer node and the viewer finds its graph, among
// `graphs` (list_graphs()): --attach ENDPOINT as given (its entry when one has that endpoint,
// else an unregistered entry: another machine's graph); else the graph named; else the first
// whose name starts with the prefix; else $ENACT_ATTACH (the graph whose launcher started this
// process); else the only one running. Of several that fit, `current` (the endpoint in use)
// is kept. nullopt: none fits (yet). Throws AmbiguousGraph when several run and none is named.
std::optional<GraphEntry> pick_graph(const AttachChoice& choice, const std::vector<GraphEntry>& graphs, const std::string& current = "");

// the graph to attach to (pick_graph), waiting for it to appear while `stop` is false
// (saying so once on `say`). Throws AmbiguousGraph when several run and none is named,
// config::Error when none appeared in wait_s.
GraphEntry find_graph(const AttachChoice& choice, std::ostream& say, const std::function<bool()>& stop);

// the line every tool prints once attached: "attached to graph NAME at ENDPOINT"
std::string attached_line(const GraphEntry& e);

}  // namespace enact::graph
