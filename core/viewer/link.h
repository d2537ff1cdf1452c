#pragma once
// The viewer's connection to a graph: one SUB socket on the attach point for the observer
// topics (decimated sim/scene, task/event, node/status, tactile/shown, param/ack and
// graph/topics, task/state: never the loop-rate ones), and a ParamClient to send param/set.
// It follows the registry (core/session/registry.h): a graph by name (connected when it appears,
// again when it is launched anew), the first graph whose name starts with a prefix (an
// experiment's current trial), or the only graph running; so a viewer started before its
// graph connects when the graph appears. The graph never notices an observer coming or going.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/bus/bytes.h"
#include "core/bus/client.h"
#include "core/bus/typed.h"
#include "core/params/param_bus.h"
#include "core/session/registry.h"
#include "core/viewer/view_model.h"
#include "msgs/graph.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"
#include "msgs/task_state.pb.h"

namespace enact::viewer {

class GraphLink {
 public:
  // `choice`: which graph (an endpoint is kept as it is, the rest is followed); `source`
  // names the viewer in the headers of what it sends; `keys` for a graph with an access file
  GraphLink(graph::AttachChoice choice, std::string source, bus::ClientKeys keys = {});
  ~GraphLink();
  GraphLink(const GraphLink&) = delete;
  GraphLink& operator=(const GraphLink&) = delete;

  // follows the registry (at most every 0.5 s); true when it moved to another graph (the
  // model should then be cleared)
  bool follow(std::int64_t now_ns);

  // takes what arrived (at most max_messages) into `model`; param answers are returned,
  // also those given up on (no answer in time)
  std::vector<graph::ParamAnswer> receive(ViewModel& model, std::int64_t now_ns, int max_messages = 2000);

  // sends a request; its id, or 0 when there is no endpoint yet
  std::uint64_t send(const msgs::ParamUpdate& update);

  // the endpoint in use ("" while no graph fits)
  const std::string& endpoint() const { return endpoint_; }
  // what the viewer attaches to, for people: the graph and endpoint, or what it waits for
  std::string describe() const;

 private:
  struct Connection;
  void connect(const std::string& endpoint);

  graph::AttachChoice choice_;
  std::string source_;
  bus::ClientKeys keys_;
  std::string endpoint_;
  std::string name_;  // the graph's, "" while none
  std::int64_t next_look_ns_ = 0;
  std::unique_ptr<Connection> connection_;
};

}  // namespace enact::viewer
