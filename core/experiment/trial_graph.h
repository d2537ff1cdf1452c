#pragma once
// One trial's graph, started and watched by the runner (private to core/experiment): the
// bridge runner (runner.cpp) and the discrimination runner (discrimination_graph.cpp) run
// every trial through run_trial_graph, so both get the same session, real-time profile,
// logger and log file.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "core/bus/bytes.h"
#include "core/session/session.h"
#include "core/launch/launch_file.h"
#include "core/rt/clock.h"

namespace enact::experiment {

// the runner's own node name on the bus (it publishes task/event: trial start, condition,
// resets, a discrimination trial's intervals and answer)
inline constexpr const char* kRunnerNode = "experiment";
// in real time the clock master stops itself at a trial's limit (or after the answer); the
// runner stops the rest of the graph this long after, once the logger has the last messages
inline constexpr double kDrain_s = 1.0;
// consecutive failed trials after which a run stops
inline constexpr int kMaxFailures = 3;

// seconds from `since_ns` (an earlier rt::now_ns(), the one clock) until now
inline double seconds_since(std::int64_t since_ns) { return static_cast<double>(rt::now_ns() - since_ns) * 1e-9; }

// a trial's graph while it runs, as the runner's watching thread sees it
class GraphRun {
 public:
  GraphRun(bus::BytePublisher& publisher, graph::GraphSession& session) : out(publisher), endpoint(session.endpoint()), session_(session) {}
  bus::BytePublisher& out;     // the runner's publisher, task/event declared at the attach point
  const std::string endpoint;  // the attach point's (subscribe there; param/set goes up there)
  // every node is ready (the supervisor said so)
  bool ready() const { return ready_.load(); }
  // the supervisor returned: the graph is down (the watcher returns then)
  bool finished() const { return finished_.load(); }
  // stop the graph: the supervisor stops it in order
  void stop() { session_.stop(); }
  // when a node of the graph ended cleanly (exit 0: the clock master at the trial's end), 0
  // while none has
  std::int64_t clean_exit_ns() const { return clean_exit_ns_.load(); }

 private:
  friend int run_trial_graph(const std::string&, const std::string&, launch::LaunchDescription, const std::string&, const std::function<void(GraphRun&)>&);
  graph::GraphSession& session_;
  std::atomic<bool> ready_{false}, finished_{false};
  std::atomic<std::int64_t> clean_exit_ns_{0};
};

// the trial graph of `launch_file` with `args`, on `clock` when given (--clock), over the
// file's own
launch::LaunchDescription load_trial_graph(const std::string& launch_file, const std::map<std::string, std::string>& args,
                                           const std::optional<rt::GraphClock>& clock);

// runs `graph` (from `launch_file`) as the graph named `name` (numbered when taken), the
// nodes' output (stdout and stderr) into `log`, under the real-time profile it asks for;
// `watch` runs on a thread of its own from the start until the graph is down (it returns once
// GraphRun::finished). Returns the supervisor's exit code.
int run_trial_graph(const std::string& name, const std::string& launch_file, launch::LaunchDescription graph, const std::string& log,
                    const std::function<void(GraphRun&)>& watch);

}  // namespace enact::experiment
