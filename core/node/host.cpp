#include "core/node/host.h"

#include <cstdio>
#include <exception>

#include "core/config/yaml.h"
#include "core/graph/launcher_pipe.h"
#include "core/graph/graph_dir.h"
#include "core/graph/process.h"
#include "core/graph/sockets.h"
#include "core/graph/stop.h"
#include "core/graph/topics.h"
#include "core/node/loop_component.h"
#include "core/params/node_params.h"
#include "core/params/param_table.h"

namespace enact::node {

Host::Host(const NodeKind& kind, graph::NodeArgs args) : kind_(kind), args_(std::move(args)) {
  args_.params.declare(*graph::node_table(kind.executable));
  if (!kind.plugins) args_.params.refuse_unknown();
}

Host::~Host() = default;

void Host::open() {
  graph::install_stop_handlers();
  // in simulated time no observer loses a message: the node waits for it instead
  const bool simulated = graph::graph_clock() == rt::GraphClock::simulated;
  if (kind_.send_hwm > 0) {
    out_ = std::make_unique<bus::BytePublisher>(graph::node_endpoint(args_.name), bus::PublisherOptions{.node = args_.name, .send_hwm = kind_.send_hwm, .wait_when_full = simulated});
    status_ = std::make_unique<bus::Publisher<msgs::NodeStatus>>(*out_, graph::kNodeStatus);
  }
  board_ = std::make_unique<graph::ParamBoard>(args_.name);
  board_->add(args_.params, args_.name);
}

void Host::announce() {
  if (out_) graph::announce_topics(*out_);
  board_->start();
}

void Host::ready() { graph::report_ready(); }

void Host::publish_status(msgs::NodeStatus& status, const std::vector<std::pair<std::string, bus::TopicCounters>>& received) {
  graph::add_counters(status, *out_, received);
  status_->publish(status);
}

int run_node(const NodeKind& kind, int argc, char** argv, const std::function<int(Host&)>& body) {
  try {
    graph::NodeArgs args = graph::parse_node_args(argc, argv, kind.default_name);
    // a container's plugin libraries first: their stages' parameters are in its --help
    if (!args.libraries.empty() && !kind.plugins) {
      throw config::Error(std::string(kind.default_name) + ": --library is for the stages of enact-rt or enact-sim\n  fix: give it to one of those (launch file: the component's library:)");
    }
    for (const std::string& library : args.libraries) load_plugin_library(library);
    if (args.help) {
      const std::string more = kind.more_help ? kind.more_help() : "";
      std::fputs((kind.help + graph::help_lines(*graph::node_table(kind.executable)) + more).c_str(), stdout);
      return 0;
    }
    if (kind.loop) graph::apply_rt_profile(args.name);
    Host host(kind, std::move(args));
    return body(host);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", kind.executable, e.what());
    return 1;
  }
}

}  // namespace enact::node
