#include "core/params/param_board.h"

#include <pthread.h>
#include <sched.h>

#include <chrono>

#include "core/graph/launcher_pipe.h"
#include "core/graph/graph_dir.h"
#include "core/graph/topics.h"

namespace enact::graph {

ParamBoard::ParamBoard(const std::string& node)
    : out_(node_endpoint(node + kParamBoardSuffix), {.node = node, .send_hwm = 100}), pub_(out_, kParamValues + node) {
  values_.set_node(node);
}

ParamBoard::~ParamBoard() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void ParamBoard::add(const Params& p, const std::string& name, const std::string& file_prefix) {
  const std::lock_guard lock(mutex_);
  for (const auto& [spec, value] : p.in_force()) {
    msgs::ParamValues::Param& v = *values_.add_params();
    v.set_name(name + "." + spec.name);
    v.set_file_name(file_prefix + spec.name);
    v.set_value(value);
    v.set_type(type_name(spec.type));
    v.set_unit(unit_of(spec.name));
    v.set_range(range_text(spec));
    v.set_doc(spec.doc);
    v.set_live(spec.live);
    v.set_at_start(spec.at_start);
  }
}

void ParamBoard::start() {
  announce_topics(out_);
  thread_ = std::thread([this] { run(); });
}

void ParamBoard::set(const std::string& name, const std::string& value) {
  {
    const std::lock_guard lock(mutex_);
    for (msgs::ParamValues::Param& v : *values_.mutable_params()) {
      if (v.name() == name) v.set_value(value);
    }
    changed_ = true;
  }
  wake_.notify_all();
}

void ParamBoard::run() {
  // a node's loop thread may run under SCHED_FIFO: this one never competes with it
  const sched_param normal{};
  pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal);
  std::unique_lock lock(mutex_);
  while (!stop_) {
    changed_ = false;
    values_.mutable_header()->set_stamp_ns(0);
    pub_.publish(values_);
    wake_.wait_for(lock, std::chrono::seconds(1), [this] { return stop_ || changed_; });
  }
}

}  // namespace enact::graph
