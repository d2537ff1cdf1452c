#include "core/session/session.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/bus/endpoints.h"
#include "core/session/launch_info.h"
#include "core/graph/topics.h"
#include "core/config/env.h"
#include "msgs/param_update.pb.h"

namespace enact::graph {
namespace {

// the prefix of a fresh graph folder, once those of killed sessions are removed;
// `supervised`: the supervisor's signals are blocked before any thread starts (the attach
// point's)
std::string folder_prefix(bool supervised) {
  if (supervised) launch::block_supervisor_signals();
  clean_stale_folders();
  return (std::filesystem::temp_directory_path() / "enact-graph-").string();
}

// the attach point's options; with an access file, the graph's own observers get a key in
// `folder` first (its files into `own`)
bus::AttachOptions attach_options(const SessionOptions& o, const std::string& folder, bus::OwnClientFiles& own) {
  bus::AttachOptions a;
  a.bind_endpoint = o.bind_endpoint;
  a.allow_remote = o.allow_remote;
  if (o.access) {
    bus::Access access = *o.access;
    own = bus::add_own_client(access, folder, "graph:observer");
    a.access = std::move(access);
  }
  // observers may send parameter changes; the nodes find them at the inbound publisher
  a.inbound_endpoint = bus::ipc_endpoint(folder, kInboundNode);
  a.inbound_topics.assign(std::begin(kInboundTopics), std::end(kInboundTopics));
  a.latched_topics = {kTaskState, kParamValues};
  return a;
}

}  // namespace

GraphSession::GraphSession(const std::string& name, const std::string& launch_file, const SessionOptions& options)
    : folder_(folder_prefix(options.supervised)),
      attach_(name, attach_options(options, folder_.path(), own_)),
      registration_(name, attach_.endpoint(), launch_file, folder_.path(), options.numbered, options.loop_cpus) {
  // a later session removes the folder if this process is killed
  std::ofstream(folder_.path() + "/launcher") << getpid() << " " << process_start(getpid()) << "\n";
  // observers see the name the registry gave (NAME-2 when NAME runs already)
  attach_.set_graph_name(registration_.entry().name);
  attach_.declare_topic<msgs::ParamUpdate>(kParamSet, "attach");
}

GraphSession::~GraphSession() { attach_.stop(); }

std::string GraphSession::node_endpoint(const std::string& node) const { return bus::ipc_endpoint(folder_.path(), node); }

std::vector<launch::Param> GraphSession::environment() const {
  // the launcher's own values (no source to name)
  std::vector<launch::Param> env{{env::kGraphDir, folder_.path(), ""}, {env::kAttach, attach_.endpoint(), ""}, {env::kGraph, name(), ""}};
  if (!own_.key.empty()) {
    env.push_back({env::kKey, own_.key, ""});
    env.push_back({env::kServerKey, own_.server_key, ""});
  }
  return env;
}

bus::ClientKeys GraphSession::own_keys() const { return own_.key.empty() ? bus::ClientKeys{} : bus::client_keys(own_.key, own_.server_key); }

int GraphSession::run(const launch::LaunchDescription& graph, const std::string& launch_path, launch::SupervisorOptions options, std::ostream& log) {
  // every node may publish: its endpoint is connected now, its topics listed as it declares them
  // (and its parameter board, param_board.h)
  for (const launch::NodeSpec& n : graph.nodes) {
    attach_.add_publisher(n.name, node_endpoint(n.name));
    attach_.add_publisher(n.name, node_endpoint(n.name + kParamBoardSuffix));
  }
  attach_.set_launch_info(launch_info(launch_path, graph));
  std::vector<launch::Param> env = environment();
  env.insert(env.end(), options.env.begin(), options.env.end());
  options.env = env;
  options.on_topic = [this](const launch::NodeSpec& n, const std::string& topic, const std::string& type) { attach_.declare_topic(topic, type, n.name); };
  options.stop = &stop_;
  return launch::supervise(graph, options, log);
}

}  // namespace enact::graph
