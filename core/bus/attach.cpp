#include "core/bus/attach.h"

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <chrono>
#include <exception>
#include <iostream>
#include <stdexcept>

#include "core/bus/context.h"
#include "core/bus/schema.h"
#include "core/bus/typed.h"
#include "core/config/yaml.h"
#include "core/rt/clock.h"
#include "msgs/graph.pb.h"
#include "msgs/param_update.pb.h"

namespace enact::bus {
namespace {


// how long a caller waits for the forwarding thread to answer a command
constexpr int kCommandTimeout_ms = 5000;
// data messages forwarded per wake-up before commands and subscriptions get a turn
constexpr int kForwardBatch = 256;

// header.source of GraphInfo
constexpr const char* kSource = "attach";

// a fresh inproc name for each attach point's command pair
std::string control_endpoint() {
  static std::atomic<unsigned> next = 0;
  return "inproc://enact.bus.attach." + std::to_string(next++);
}

}  // namespace

int observer_queue_messages(std::size_t queue_bytes, std::size_t cost_bytes) {
  if (cost_bytes == 0) return kObserverQueue;
  return static_cast<int>(std::clamp<std::size_t>(queue_bytes / cost_bytes, 1, kObserverQueue));
}

AttachPoint::AttachPoint(std::string graph, AttachOptions options)
    : graph_(std::move(graph)),
      graph_period_ms_(options.graph_period_ms),
      xpub_(make_socket(zmq::socket_type::xpub)),
      xsub_(make_socket(zmq::socket_type::xsub)),
      control_(make_socket(zmq::socket_type::pair)),
      requester_(make_socket(zmq::socket_type::pair)),
      inbound_(make_socket(zmq::socket_type::pub)),
      inbound_topics_(options.inbound_topics),
      latched_topics_(options.latched_topics),
      access_(std::move(options.access)),
      refused_ack_topic_(options.refused_ack_topic),
      descriptor_set_(msgs_descriptor_set()),
      observer_queue_(observer_queue_messages(options.observer_queue_bytes, kMeanCost_bytes)) {
  // refuse a bad or exposed endpoint before binding it
  const std::string& bind = options.bind_endpoint;
  validate_endpoint(bind, "attach endpoint");
  if (!is_local(bind) && !(options.allow_remote && access_)) {
    throw config::Error("attach endpoint '" + bind + "': other machines can reach it" +
                        (access_ ? ", and allow_remote is not set" : ", and there is no access file: anyone could see every topic and change parameters") +
                        "\n  fix: bind tcp://127.0.0.1:PORT (or ipc://PATH), or set allow_remote with an access file (enact launch --allow-remote --access ACCESS.yaml)");
  }
  if (graph_period_ms_ < 1) {
    throw config::Error("attach point: graph_period_ms must be >= 1, got " + std::to_string(graph_period_ms_) +
                        "\n  fix: give the GraphInfo period in ms, e.g. 1000");
  }
  // observers' side: every subscription reaches us (so each new observer of graph/topics
  // gets a GraphInfo at once); lossy, so a slow observer never holds the publishers back
  // (in real time: a graph in simulated time waits for its observers, see forward_data)
  xpub_.set(zmq::sockopt::xpub_verbose, true);
  // deep queues both ways (seconds of a 5 kHz graph's every topic), so an observer that
  // pauses (a logger compressing a chunk) loses nothing
  xpub_.set(zmq::sockopt::sndhwm, observer_queue_);
  xsub_.set(zmq::sockopt::rcvhwm, kObserverQueue);
  // with an access file, only its keys connect, and what they send passes its gate
  if (access_) {
    LogFn log = options.log ? options.log : [](const std::string& line) { std::cerr << "attach point: " << line << "\n"; };
    curve_ = std::make_unique<CurveServer>(xpub_, *access_, log);
    gate_ = std::make_unique<InboundGate>(*access_, log);
  }
  try {
    xpub_.bind(bind);
  } catch (const zmq::error_t& e) {
    throw config::Error("attach endpoint '" + bind + "': cannot bind: " + e.what() +
                        "\n  fix: choose a free port (or * for any)");
  }
  endpoint_ = xpub_.get(zmq::sockopt::last_endpoint);
  // what observers send, republished for the nodes
  if (!options.inbound_endpoint.empty()) {
    validate_endpoint(options.inbound_endpoint, "inbound endpoint");
    try {
      inbound_.bind(options.inbound_endpoint);
    } catch (const zmq::error_t& e) {
      throw config::Error("inbound endpoint '" + options.inbound_endpoint + "': cannot bind: " + e.what() +
                          "\n  fix: choose an ipc path no node binds");
    }
  } else {
    inbound_topics_.clear();
  }
  // command pair, then the thread (it owns xpub_, xsub_ and control_ from now on)
  const std::string control = control_endpoint();
  control_.bind(control);
  requester_.connect(control);
  requester_.set(zmq::sockopt::rcvtimeo, kCommandTimeout_ms);
  requester_.set(zmq::sockopt::sndtimeo, kCommandTimeout_ms);
  thread_ = std::thread([this] { run(); });
}

AttachPoint::~AttachPoint() { stop(); }

void AttachPoint::add_publisher(const std::string& node, const std::string& endpoint) {
  validate_endpoint(endpoint, "publisher endpoint of node '" + node + "'");
  request({"connect", endpoint});
}

void AttachPoint::declare_topic(const std::string& name, const std::string& type, const std::string& publisher) {
  request({"topic", name, type, publisher});
}

void AttachPoint::set_graph_name(const std::string& graph) { request({"name", graph}); }

void AttachPoint::set_launch_info(const msgs::GraphInfo& launch) {
  const std::lock_guard lock(launch_mutex_);
  // how the graph was started: every field but those the attach point fills itself
  launch_ = launch;
  launch_.clear_header();
  launch_.clear_graph();
  launch_.clear_topics();
  launch_.clear_descriptor_set();
  lossless_.store(launch.clock() == "simulated");
}

void AttachPoint::stop() {
  if (!thread_.joinable()) return;
  if (!failed_) request({"stop"});
  thread_.join();
}

void AttachPoint::request(std::initializer_list<std::string_view> frames) {
  const std::lock_guard lock(request_mutex_);
  if (failed_) throw std::runtime_error("attach point stopped: " + failure_);
  if (!thread_.joinable()) throw std::logic_error("attach point: used after stop()");
  send_frames(requester_, frames);
  const std::vector<std::string> answer = receive_frames(requester_);
  if (answer.size() != 1) throw std::runtime_error("attach point: no answer from the forwarding thread");
  if (!answer[0].empty()) throw std::runtime_error("attach point: " + answer[0]);
}

void AttachPoint::run() {
  try {
    zmq::pollitem_t items[] = {
        {xsub_.handle(), 0, ZMQ_POLLIN, 0},
        {xpub_.handle(), 0, ZMQ_POLLIN, 0},
        {control_.handle(), 0, ZMQ_POLLIN, 0},
    };
    // the state topics come here even while nobody observes them (kept subscribed: see below)
    for (const std::string& topic : latched_topics_) {
      const std::string subscribe = '\x01' + topic;
      (void)xsub_.send(zmq::const_buffer(subscribe.data(), subscribe.size()), zmq::send_flags::dontwait);
    }
    std::int64_t next_graph_ns = rt::now_ns();
    for (;;) {
      // sleep until traffic, a command or the next GraphInfo
      try {
        zmq::poll(items, 3, std::chrono::milliseconds(rt::ms_until(next_graph_ns)));
      } catch (const zmq::error_t& e) {
        if (e.num() != EINTR) throw;
        continue;
      }
      bool graph_now = rt::now_ns() >= next_graph_ns;
      if (items[0].revents & ZMQ_POLLIN) forward_data();
      if (items[1].revents & ZMQ_POLLIN) graph_now |= forward_from_observers();
      if (items[2].revents & ZMQ_POLLIN) {
        if (!handle_command()) return;
        graph_now = true;
      }
      if (graph_now) {
        publish_graph();
        next_graph_ns = rt::now_ns() + std::int64_t{graph_period_ms_} * 1'000'000;
        // what the queues of a slow observer took goes back to the system once drained
        malloc_trim(0);
      }
    }
  } catch (const std::exception& e) {
    failure_ = e.what();
    failed_ = true;
  }
}

bool AttachPoint::handle_command() {
  const std::vector<std::string> command = receive_frames(control_);
  std::string error;
  bool keep_running = true;
  if (command.size() == 2 && command[0] == "connect") {
    try {
      xsub_.connect(command[1]);
    } catch (const zmq::error_t& e) {
      error = "cannot connect to '" + command[1] + "': " + e.what();
    }
  } else if (command.size() == 4 && command[0] == "topic") {
    const bool known = std::any_of(topics_.begin(), topics_.end(), [&](const Topic& t) { return t.name == command[1] && t.publisher == command[3]; });
    if (!known) topics_.push_back({command[1], command[2], command[3]});
  } else if (command.size() == 2 && command[0] == "name") {
    graph_ = command[1];
  } else if (command.size() == 1 && command[0] == "stop") {
    keep_running = false;
  } else {
    error = "unknown command";
  }
  send_frames(control_, {error});
  return keep_running;
}

void AttachPoint::forward_data() {
  // in simulated time a full observer is waited for (and so, in turn, are the publishers)
  if (lossless_.load() != nodrop_) {
    nodrop_ = lossless_.load();
    xpub_.set(zmq::sockopt::xpub_nodrop, nodrop_);
    // ... and a graph that ended still delivers what its observers have not taken (bytes.h)
    xpub_.set(zmq::sockopt::linger, nodrop_ ? kFullLinger_ms : kPublisherLinger_ms);
  }
  // publishers -> observers, whole messages, a batch at a time; the last of a state topic kept
  for (int i = 0; i < kForwardBatch; ++i) {
    // the whole message first
    std::size_t n = 0;
    for (bool more = true; more; ++n) {
      if (n == frames_.size()) frames_.emplace_back();
      if (n == 0 && recv_frame(xsub_, frames_[0], zmq::recv_flags::dontwait) != Received::frame) return;
      if (n > 0) recv_more(xsub_, frames_[n]);
      more = frames_[n].more();
    }
    std::vector<std::string>* keep = nullptr;
    if (latched(frames_[0].to_string_view())) {
      keep = &latched_[frames_[0].to_string()];
      keep->clear();
    }
    // copies, each of its own size: a received frame shares ZeroMQ's 8 kB receive buffer
    // with its neighbours, which a slow observer's queue would otherwise keep whole
    for (std::size_t k = 0; k < n; ++k) {
      if (keep) keep->push_back(frames_[k].to_string());
      const auto flags = k + 1 < n ? zmq::send_flags::sndmore | zmq::send_flags::dontwait : zmq::send_flags::dontwait;
      (void)send_frame(xpub_, frames_[k].data(), frames_[k].size(), flags, nodrop_);
    }
  }
}

bool AttachPoint::forward_from_observers() {
  // subscriptions go to the publishers, messages on inbound topics to the nodes; true when
  // someone (re)subscribed to graph/topics
  bool wants_graph = false;
  zmq::message_t notice;
  for (Received got; (got = recv_frame(xpub_, notice, zmq::recv_flags::dontwait)) != Received::none;) {
    if (got == Received::interrupted) continue;
    if (notice.more()) {
      relay_inbound(notice);
      continue;
    }
    const std::string_view n = notice.to_string_view();
    if (n.empty() || (n.front() != 0 && n.front() != 1)) continue;  // a stray one-frame message
    if (n.front() == 1 && kGraphTopic.starts_with(n.substr(1))) wants_graph = true;
    if (n.front() == 1) send_latched(n.substr(1));
    if (n.front() == 0 && latched(n.substr(1))) continue;  // the attach point's own subscription stays
    (void)xsub_.send(notice, zmq::send_flags::dontwait);
  }
  return wants_graph;
}

void AttachPoint::relay_inbound(zmq::message_t& first) {
  // the rest of the message is there already (multipart messages arrive whole)
  std::vector<zmq::message_t> frames;
  frames.push_back(std::move(first));
  while (frames.back().more()) {
    frames.emplace_back();
    recv_more(xpub_, frames.back());
  }
  // a bus message (topic, type, payload) on an inbound topic, else dropped
  if (frames.size() != 3) return;
  const std::string_view topic = frames[0].to_string_view();
  if (std::find(inbound_topics_.begin(), inbound_topics_.end(), topic) == inbound_topics_.end()) return;
  // with keys: the sender's role and rate decide; what passes names its key (audit trail)
  const std::string key(sender_key(frames[0]));
  if (gate_) {
    const Verdict v = gate_->check(key, rt::now_ns());
    if (!v.pass) {
      if (v.answer) refuse_inbound(frames, v.reason);
      return;
    }
  }
  frames[2] = zmq::message_t(with_sender_key(frames[2].to_string_view(), key));
  // to the nodes, and to the observers of that topic
  for (zmq::socket_t* out : {&inbound_, &xpub_}) {
    for (std::size_t i = 0; i < frames.size(); ++i) {
      zmq::message_t copy;
      copy.copy(frames[i]);
      const auto flags = i + 1 < frames.size() ? zmq::send_flags::sndmore | zmq::send_flags::dontwait : zmq::send_flags::dontwait;
      if (!out->send(copy, flags)) break;
    }
  }
}

bool AttachPoint::latched(std::string_view topic) const {
  return std::any_of(latched_topics_.begin(), latched_topics_.end(),
                     [&](const std::string& t) { return t == topic || (t.ends_with('/') && topic.starts_with(t)); });
}

void AttachPoint::send_latched(std::string_view prefix) {
  // the subscription is in force already: the new observer receives these
  for (const auto& [topic, frames] : latched_) {
    if (!std::string_view(topic).starts_with(prefix)) continue;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const auto flags = i + 1 < frames.size() ? zmq::send_flags::sndmore | zmq::send_flags::dontwait : zmq::send_flags::dontwait;
      if (!xpub_.send(zmq::const_buffer(frames[i].data(), frames[i].size()), flags)) break;
    }
  }
}

void AttachPoint::refuse_inbound(const std::vector<zmq::message_t>& frames, const std::string& reason) {
  // only a parameter change has an answer to wait for: a ParamAck, refused, with the reason
  msgs::ParamUpdate update;
  if (frames[1].to_string_view() != msgs::ParamUpdate::descriptor()->full_name() || !update.ParseFromArray(frames[2].data(), static_cast<int>(frames[2].size()))) return;
  msgs::ParamAck ack;
  msgs::Header& h = *ack.mutable_header();
  h.set_seq(++refused_seq_);
  h.set_stamp_ns(rt::now_ns());
  h.set_source(kSource);
  ack.set_request_id(update.request_id());
  ack.set_applied(false);
  ack.set_reason(reason);
  publish_own(refused_ack_topic_, msgs::ParamAck::descriptor()->full_name(), ack.SerializeAsString());
}

void AttachPoint::publish_own(std::string_view topic, const std::string& type, const std::string& payload) {
  constexpr auto more = zmq::send_flags::sndmore | zmq::send_flags::dontwait;
  // nobody subscribed or a full queue: this one is skipped
  if (!xpub_.send(zmq::const_buffer(topic.data(), topic.size()), more)) return;
  (void)xpub_.send(zmq::const_buffer(type.data(), type.size()), more);
  (void)xpub_.send(zmq::const_buffer(payload.data(), payload.size()), zmq::send_flags::dontwait);
}

void AttachPoint::publish_graph() {
  msgs::GraphInfo info;
  msgs::Header& h = *info.mutable_header();
  h.set_seq(++graph_seq_);
  h.set_stamp_ns(rt::now_ns());
  h.set_source(kSource);
  info.set_graph(graph_);
  for (const Topic& t : topics_) {
    msgs::GraphInfo::TopicInfo& out = *info.add_topics();
    out.set_name(t.name);
    out.set_type(t.type);
    out.set_publisher(t.publisher);
  }
  info.set_descriptor_set(descriptor_set_);
  {
    const std::lock_guard lock(launch_mutex_);
    info.MergeFrom(launch_);
  }
  // skipped when nobody subscribed or the queue is full: the next one follows in a period
  publish_own(kGraphTopic, msgs::GraphInfo::descriptor()->full_name(), info.SerializeAsString());
}

AttachSender::AttachSender(const std::string& endpoint, std::string source, const ClientKeys& keys)
    : socket_(make_socket(zmq::socket_type::xsub)), source_(std::move(source)) {
  // it sends multipart messages: linger like a publisher (context.h)
  socket_.set(zmq::sockopt::linger, kPublisherLinger_ms);
  attach_connect(socket_, endpoint, keys);
}

bool AttachSender::send_bytes(std::string_view topic, std::string_view type, const std::string& payload) {
  // XSUB passes a message upstream whose frames do not start with the subscription bytes 0
  // and 1: a topic and a type name never do, a Protobuf payload never does (no field 0)
  constexpr auto more = zmq::send_flags::sndmore | zmq::send_flags::dontwait;
  try {
    if (!socket_.send(zmq::const_buffer(topic.data(), topic.size()), more)) return false;
    (void)socket_.send(zmq::const_buffer(type.data(), type.size()), more);
    (void)socket_.send(zmq::const_buffer(payload.data(), payload.size()), zmq::send_flags::dontwait);
  } catch (const zmq::error_t&) {
    return false;
  }
  return true;
}

}  // namespace enact::bus
