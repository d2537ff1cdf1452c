#pragma once
// Running a launch description: start the processes in order, wait until each reports
// ready, supervise them, and stop them in reverse order (list the drivers last: they stop
// first, zeroing force and lowering pins). No process outlives the launcher: when it dies,
// even by SIGKILL, each process gets SIGTERM (PR_SET_PDEATHSIG) and stops cleanly.
//
// Ready protocol: each process gets ENACT_READY_FD=<fd> in its environment and writes a
// line "ready\n" to that file descriptor once it is active. Before it, it may write:
//   "topic NAME TYPE\n"  it publishes topic NAME of message type TYPE (passed to on_topic)
//   "wait S\n"           it waits up to S s for something (observers) before it is ready:
//                        its ready timeout is extended by S from then
#include <atomic>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "core/launch/launch_file.h"

namespace enact::launch {

struct SupervisorOptions {
  double ready_timeout_s = 10.0;  // per process, from its start to its "ready"
  double duration_s = 0.0;        // > 0: stop the graph cleanly after this long
  double stop_timeout_s = 3.0;    // SIGTERM, then SIGKILL after this long
  std::vector<Param> env;         // set in every process's environment (before its own env)
  // called once every process is ready (e.g. to print where observers attach)
  std::function<void()> on_ready;
  // a process declared a topic it publishes (on its ready pipe)
  std::function<void(const NodeSpec& node, const std::string& topic, const std::string& type)> on_topic;
  // a process exited (its wait status), before the graph acts on it (from the supervisor's thread)
  std::function<void(const NodeSpec& node, int status)> on_exit;
  // set from any thread: the graph stops in order, as on SIGTERM (checked every 50 ms)
  const std::atomic<bool>* stop = nullptr;
  // polled while the graph runs (about every 50 ms): the names of processes that hang (e.g.
  // graph::StatusWatch: no node/status for 3 s). Each is stopped (SIGTERM, then SIGKILL) and
  // handled as if it had exited: a required one stops the graph, a respawning one restarts.
  std::function<std::vector<std::string>()> hung_nodes;
};

// block SIGINT, SIGTERM and SIGCHLD in the calling thread; call it before starting any
// other thread of the launcher (threads inherit the mask), so that every such signal reaches
// the supervisor's signalfd and none is delivered (and lost, or fatal) elsewhere
void block_supervisor_signals();

// runs the graph until SIGINT/SIGTERM, options.stop, --duration, or the exit of a required process.
// Returns 0 after a requested stop, 1 when a required process exited or a process did not
// become ready (the message says which and why). Progress lines go to `log`.
int supervise(const LaunchDescription& graph, const SupervisorOptions& options, std::ostream& log);

}  // namespace enact::launch
