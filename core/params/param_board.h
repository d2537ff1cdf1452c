#pragma once
// A node's parameters as they stand, for the graph's observers (docs/parameters.md): every
// parameter it declares (its components' included) with the value in force, on
// param/values/<node> (msgs/param_update.proto, ParamValues). Its own thread publishes from
// its own endpoint, node_endpoint(node + kParamBoardSuffix), once a second and at once after
// a live change, so no loop thread ever serialises or sends it; the attach point keeps the
// last message of each node for observers that come later (enact param list, get, dump).
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "core/bus/bytes.h"
#include "core/bus/typed.h"
#include "core/params/params.h"
#include "msgs/param_update.pb.h"

namespace enact::graph {

class ParamBoard {
 public:
  // binds node_endpoint(node + kParamBoardSuffix); nothing is sent before start()
  explicit ParamBoard(const std::string& node);
  // stops its thread
  ~ParamBoard();
  ParamBoard(const ParamBoard&) = delete;
  ParamBoard& operator=(const ParamBoard&) = delete;

  // adds every parameter `p` declared, with its value in force (commands left out):
  // named "<name>.<param>" on the bus, "<file_prefix><param>" in a param_file
  void add(const Params& p, const std::string& name, const std::string& file_prefix = "");
  // tells the launcher its topic (with the node's others, before "ready") and starts publishing
  void start();
  // a live change applied: parameter `name` ("<node>.<param>") is now `value`. Thread-safe.
  void set(const std::string& name, const std::string& value);

 private:
  void run();

  bus::BytePublisher out_;
  bus::Publisher<msgs::ParamValues> pub_;
  std::mutex mutex_;
  std::condition_variable wake_;
  msgs::ParamValues values_;  // under mutex_
  bool changed_ = false, stop_ = false;
  std::thread thread_;
};

}  // namespace enact::graph
