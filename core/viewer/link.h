#pragma once
// The viewer's connection to a graph: one SUB socket on the attach point for the observer
// topics (decimated sim/scene, task/event, node/status, tactile/shown, param/ack and
// graph/topics: never the loop-rate ones), and a ParamClient to send param/set. Given no
// endpoint it follows the attach file of the last graph launched on this machine, so a
// viewer started before its graph connects when the graph appears, and moves to the next
// graph launched. The graph never notices an observer coming or going.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/bus/bytes.h"
#include "core/bus/client.h"
#include "core/bus/typed.h"
#include "core/graph/param_bus.h"
#include "core/viewer/view_model.h"
#include "msgs/graph.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"

namespace enact::viewer {

class GraphLink {
 public:
  // `endpoint`: the attach point's ("" follows graph::attach_file()); `source` names the
  // viewer in the headers of what it sends; `keys` for a graph with an access file
  GraphLink(std::string endpoint, std::string source, bus::ClientKeys keys = {});
  ~GraphLink();
  GraphLink(const GraphLink&) = delete;
  GraphLink& operator=(const GraphLink&) = delete;

  // follows the attach file (at most every 0.5 s); true when it moved to another endpoint
  // (the model should then be cleared)
  bool follow(std::int64_t now_ns);

  // takes what arrived (at most max_messages) into `model`; param answers are returned,
  // also those given up on (no answer in time)
  std::vector<graph::ParamAnswer> receive(ViewModel& model, std::int64_t now_ns, int max_messages = 2000);

  // sends a request; its id, or 0 when there is no endpoint yet
  std::uint64_t send(const msgs::ParamUpdate& update);

  // the endpoint in use ("" while the attach file names none)
  const std::string& endpoint() const { return endpoint_; }
  // what the viewer attaches to, for people: the endpoint, or the attach file it waits on
  std::string describe() const;

 private:
  struct Connection;
  void connect(const std::string& endpoint);

  bool follow_file_;
  std::string source_;
  bus::ClientKeys keys_;
  std::string endpoint_;
  std::int64_t next_look_ns_ = 0;
  std::unique_ptr<Connection> connection_;
};

}  // namespace enact::viewer
