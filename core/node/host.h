#pragma once
// The node host: what every node process of a graph does around its component. It reads
// the command line (--name, --param, --component, --library, --help, --check), loads a
// container's plugin libraries (node/loop_component.h), gives --help from the
// node's parameter table, applies the launcher's real-time profile to a loop process before
// any socket, declares the table and refuses unknown parameters; then it takes the component
// through its lifecycle (host_main): the component reads its parameters (the launcher's
// --check stops there, binding nothing); the host installs the stop handlers, binds the
// node's publisher and its parameter board; the component makes its ports, the host tells
// the launcher its topics; the component activates, the host says "ready"; the component
// runs until a stop request and deactivates. Errors reach stderr as "enact-x: error: ...",
// exit 1.
//
//   int main(int argc, char** argv) { return enact::node::host_main<enact::node::Tactile>(enact::node::kTactile, argc, argv); }
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/bus/bytes.h"
#include "core/bus/typed.h"
#include "core/params/param_board.h"
#include "core/params/params.h"
#include "msgs/node_status.pb.h"

namespace enact::node {

// what a node executable is
struct NodeKind {
  const char* executable;    // its name, and the key of its parameter table (graph::node_table)
  const char* default_name;  // the node's name without --name
  const char* help;          // usage and what it does; the parameter list follows
  bool loop = false;         // a loop process: the launcher's real-time profile applies
  bool plugins = false;      // it hosts components (--component): it checks their parameters itself
  // messages its publisher queues per subscriber (0: it publishes nothing of its own and has
  // none; in simulated time it waits for a full subscriber instead of dropping:
  // bus::PublisherOptions::wait_when_full)
  int send_hwm = 1000;
  std::string (*more_help)() = nullptr;  // after the parameter list (a container's components)
};

class Host {
 public:
  Host(const NodeKind& kind, graph::NodeArgs args);
  Host(const Host&) = delete;
  Host& operator=(const Host&) = delete;
  ~Host();

  const std::string& name() const { return args_.name; }
  graph::Params& params() { return args_.params; }
  const graph::NodeArgs& args() const { return args_; }
  // only checking the parameters (--check): the component is made, then nothing runs
  bool checking() const { return args_.check; }

  // the node's publisher and parameter board (its own parameters added), bound by open()
  bus::BytePublisher& out() { return *out_; }
  graph::ParamBoard& board() { return *board_; }
  // stop handlers, publisher, parameter board
  void open();
  // every typed publisher made: the launcher is told the topics, the board starts
  void announce();
  // the component is active: the launcher is told so (the one "ready" of the process)
  void ready();
  // the node's status, once a second: the counters of its publisher and `received` (its
  // subscriber's: ByteSubscriber::all_counters) added, published on node/status
  void publish_status(msgs::NodeStatus& status, const std::vector<std::pair<std::string, bus::TopicCounters>>& received = {});

 private:
  const NodeKind& kind_;
  graph::NodeArgs args_;
  std::unique_ptr<bus::BytePublisher> out_;
  std::unique_ptr<bus::Publisher<msgs::NodeStatus>> status_;
  std::unique_ptr<graph::ParamBoard> board_;
};

// runs `body` as node `kind` (see above); its result is the exit code
int run_node(const NodeKind& kind, int argc, char** argv, const std::function<int(Host&)>& body);

// a node process running component C, which has one lifecycle:
//   C(Host&)           configure: read and check its parameters, make its device
//   void open_ports()  its publishers and subscribers, on the host's publisher
//   void activate()    devices on, peers awaited: what must hold before the node is ready
//   void run()         until a stop request, or until its own work is done
//   int deactivate()   devices safe (zero force, pins down), its summary said: the exit code
template <class C>
int host_main(const NodeKind& kind, int argc, char** argv) {
  return run_node(kind, argc, argv, [](Host& host) {
    C component(host);
    if (host.checking()) return 0;
    host.open();
    component.open_ports();
    host.announce();
    component.activate();
    host.ready();
    component.run();
    return component.deactivate();
  });
}

}  // namespace enact::node
