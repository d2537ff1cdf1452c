#include "core/foxglove/bridge.h"

#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/bus/endpoints.h"
#include "core/bus/schema.h"
#include "core/config/yaml.h"
#include "core/foxglove/parameters.h"
#include "core/params/param_bus.h"
#include "core/session/registry.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"

namespace enact::foxglove {
namespace {

using nlohmann::json;

constexpr std::uint8_t kMessageData = 0x01;  // binary opcode, both directions
constexpr std::int64_t kRateWindow_ns = 200'000'000;  // a loop-rate topic is limited within 0.2 s

void put_le(std::string& out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

std::uint32_t get_le32(const std::string& in, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(in[at + i])) << (8 * i);
  return v;
}

bool loopback_host(const std::string& host) { return host.starts_with("127.") || host == "::1" || host == "localhost"; }

std::string status(int level, const std::string& message) { return json{{"op", "status"}, {"level", level}, {"message", message}}.dump(); }

constexpr int kInfo = 0, kError = 2;  // status levels

// the topics the bridge receives whatever clients want: the graph, every node's parameters
// (param/values/<node>: the parameters capability), the answers to changes
constexpr const char* kReceivedAlways[] = {bus::kGraphTopic.data(), graph::kParamValues, graph::kParamAck};

bool received_always(const std::string& topic) {
  return std::any_of(std::begin(kReceivedAlways), std::end(kReceivedAlways), [&](const char* t) { return topic.starts_with(t); });
}

// `topic` when a client may publish on it (one of the graph's inbound topics, with or
// without a leading '/'), else ""
std::string inbound_topic(std::string_view topic) {
  if (topic.starts_with('/')) topic.remove_prefix(1);
  for (const char* t : graph::kInboundTopics) {
    if (topic == t) return t;
  }
  return "";
}

}  // namespace

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    // 3 bytes -> 4 characters of 6 bits, '=' for the missing ones at the end
    std::uint32_t v = static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 2]);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=');
    out.push_back(i + 2 < bytes.size() ? kAlphabet[v & 63] : '=');
  }
  return out;
}

Bridge::Bridge(BridgeOptions options) : options_(std::move(options)) {
  bus::validate_endpoint(options_.attach, "attach endpoint");
  connect(options_.attach);
  net::WsHandlers h;
  h.on_open = [this](net::ClientId c) { on_open(c); };
  h.on_close = [this](net::ClientId c) { on_close(c); };
  h.on_text = [this](net::ClientId c, const std::string& t) { on_text(c, t); };
  h.on_binary = [this](net::ClientId c, const std::string& d) { on_binary(c, d); };
  try {
    server_ = std::make_unique<net::WsServer>(options_.host, options_.port, kSubprotocol, std::move(h), options_.max_backlog_bytes);
  } catch (const std::runtime_error& e) {
    throw config::Error(std::string(e.what()) + "\n  fix: give a free port with --port, or stop what uses it");
  }
}

Bridge::~Bridge() { server_->stop(); }

int Bridge::port() const { return server_->port(); }

void Bridge::connect(const std::string& endpoint) {
  sub_ = std::make_unique<bus::ByteSubscriber>();
  sub_->set_receive_hwm(100'000);
  bus::attach_connect(sub_->socket(), endpoint, options_.keys);
  sub_->subscribe(std::string(bus::kGraphTopic));
  sub_->subscribe(graph::kParamAck);  // and each param/values/<node> as the graph lists it (take_graph)
  zmq_topics_.clear();
  scene_.reset();
  scene_in_use_.reset();
  graph_seen_ns_ = rt::now_ns();
  std::lock_guard lock(mutex_);
  options_.attach = endpoint;
  // client publishing only where nobody from another machine can reach either side
  param_out_.reset();
  if (bus::is_local(endpoint) && loopback_host(options_.host)) param_out_ = std::make_unique<graph::ParamClient>(endpoint, "foxglove", options_.keys);
  requests_.clear();
  boards_.clear();
  // the old graph's channels are gone: its clients are told, they subscribe to the new ones
  json gone = json::array();
  for (const Channel& ch : channels_) gone.push_back(ch.id);
  channels_.clear();
  subscriptions_changed_ = true;
  for (auto& [c, client] : clients_) {
    client.subscription_of.clear();
    client.last_sent_ns.clear();
    if (!gone.empty()) server_->send(c, json{{"op", "unadvertise"}, {"channelIds", gone}}.dump(), false);
  }
}

bool Bridge::follow_graph(std::int64_t now_ns) {
  if (now_ns - graph_seen_ns_ < kGraphSilence_ns || now_ns < next_look_ns_) return true;
  next_look_ns_ = now_ns + 1'000'000'000;
  if (options_.graph_name.empty()) {
    std::fprintf(stderr, "enact foxglove: the graph at %s sent nothing for %lld s: it stopped\n  fix: start enact foxglove again once it runs (with --graph NAME it follows a graph of that name)\n",
                 options_.attach.c_str(), static_cast<long long>(kGraphSilence_ns / 1'000'000'000));
    return false;
  }
  if (!waiting_) std::fprintf(stderr, "enact foxglove: graph %s stopped; waiting for a graph of that name to start again (Ctrl-C ends)\n", options_.graph_name.c_str());
  waiting_ = true;
  for (const graph::GraphEntry& e : graph::list_graphs()) {
    if (e.name != options_.graph_name || e.endpoint == options_.attach) continue;
    std::fprintf(stderr, "enact foxglove: graph %s started again at %s: following it\n", e.name.c_str(), e.endpoint.c_str());
    connect(e.endpoint);
    waiting_ = false;
    break;
  }
  return true;
}

BridgeStats Bridge::stats() const {
  std::lock_guard lock(mutex_);
  BridgeStats s = stats_;
  s.clients = clients_.size();
  return s;
}

const Bridge::Channel* Bridge::channel_of(const std::string& topic) const {
  for (const Channel& c : channels_) {
    if (c.topic == topic) return &c;
  }
  return nullptr;
}

std::string Bridge::advertise_json(const std::vector<const Channel*>& channels) const {
  json list = json::array();
  for (const Channel* c : channels) {
    list.push_back({{"id", c->id},
                    {"topic", c->topic},
                    {"encoding", "protobuf"},
                    {"schemaName", c->type},
                    {"schema", c->schema_base64},
                    {"schemaEncoding", "protobuf"},
                    {"maxRateHz", options_.max_rate_hz},
                    {"rateLimit", "when this topic runs faster than " + std::to_string(static_cast<int>(options_.max_rate_hz)) +
                                      " Hz (the loop-rate topics), each client gets at most that rate (the first message of each interval)"}});
  }
  return json{{"op", "advertise"}, {"channels", list}}.dump();
}

// --- WebSocket thread

void Bridge::on_open(net::ClientId c) {
  std::lock_guard lock(mutex_);  // param_out_ and the endpoint change when the graph restarts
  json capabilities = {"parameters", "parametersSubscribe"};
  if (param_out_) capabilities.push_back("clientPublish");
  json info = {{"op", "serverInfo"},
               {"name", "enact"},
               {"capabilities", capabilities},
               {"metadata", {{"graph", options_.attach}, {"maxRateHz", std::to_string(options_.max_rate_hz)}}},
               {"sessionId", std::to_string(rt::wall_ns())}};
  if (param_out_) info["supportedEncodings"] = kClientEncodings;
  clients_[c];
  server_->send(c, info.dump(), false);
  std::vector<const Channel*> all;
  for (const Channel& ch : channels_) all.push_back(&ch);
  if (!all.empty()) server_->send(c, advertise_json(all), false);
}

void Bridge::on_close(net::ClientId c) {
  std::lock_guard lock(mutex_);
  clients_.erase(c);
  subscriptions_changed_ = true;
}

void Bridge::on_text(net::ClientId c, const std::string& text) {
  const json msg = json::parse(text, nullptr, false);
  std::lock_guard lock(mutex_);
  Client& client = clients_[c];
  const std::string op = msg.is_object() ? msg.value("op", "") : "";
  try {
    if (op == "subscribe") {
      for (const json& s : msg.at("subscriptions")) {
        const auto channel = s.at("channelId").get<std::uint32_t>();
        const auto it = std::find_if(channels_.begin(), channels_.end(), [&](const Channel& ch) { return ch.id == channel; });
        if (it == channels_.end()) server_->send(c, status(2, "no channel " + std::to_string(channel)), false);
        else client.subscription_of[channel] = s.at("id").get<std::uint32_t>();
      }
      subscriptions_changed_ = true;
    } else if (op == "unsubscribe") {
      for (const json& id : msg.at("subscriptionIds")) {
        std::erase_if(client.subscription_of, [&](const auto& kv) { return kv.second == id.get<std::uint32_t>(); });
      }
      subscriptions_changed_ = true;
    } else if (op == "advertise" && param_out_) {
      advertise_from(c, client, msg.at("channels"));
    } else if (op == "unadvertise" && param_out_) {
      for (const json& id : msg.at("channelIds")) {
        client.published.erase(id.get<std::uint32_t>());
        client.unrouted.erase(id.get<std::uint32_t>());
      }
    } else if (op == "getParameters") {
      get_parameters(c, msg);
    } else if (op == "setParameters") {
      set_parameters(c, msg);
    } else if (op == "subscribeParameterUpdates" || op == "unsubscribeParameterUpdates") {
      follow_parameters(client, msg.at("parameterNames"), op == "subscribeParameterUpdates");
    } else {
      server_->send(c, status(1, "unsupported operation '" + op + "'"), false);
    }
  } catch (const json::exception& e) {
    server_->send(c, status(2, "malformed '" + op + "' message: " + e.what()), false);
  }
}

void Bridge::advertise_from(net::ClientId c, Client& client, const json& channels) {
  for (const json& ch : channels) {
    const std::string topic = inbound_topic(ch.at("topic").get<std::string>()), encoding = ch.value("encoding", "");
    const bool known_encoding = std::find(std::begin(kClientEncodings), std::end(kClientEncodings), encoding) != std::end(kClientEncodings);
    if (!topic.empty() && known_encoding && ch.value("schemaName", "") == msgs::ParamUpdate::descriptor()->full_name()) {
      client.published[ch.at("id").get<std::uint32_t>()] = {topic, encoding};
    } else if (topic.empty()) {
      client.unrouted.insert(ch.at("id").get<std::uint32_t>());
    } else {
      server_->send(c, status(kError, "only param/set (schema enact.msgs.ParamUpdate, encoding json or protobuf) may be published, not " +
                                          ch.value("topic", "?") + " (" + ch.value("schemaName", "?") + ", " + encoding + ")"), false);
    }
  }
}

void Bridge::on_binary(net::ClientId c, const std::string& data) {
  std::lock_guard lock(mutex_);
  if (!param_out_ || data.size() < 5 || static_cast<std::uint8_t>(data[0]) != kMessageData) return;
  const Client& client = clients_[c];
  const std::uint32_t channel = get_le32(data, 1);
  if (client.unrouted.contains(channel)) return;  // a panel's own topic: dropped
  const auto it = client.published.find(channel);
  if (it == client.published.end()) {
    server_->send(c, status(kError, "a message on channel " + std::to_string(channel) + ", which this client did not advertise"), false);
    return;
  }
  msgs::ParamUpdate update;
  if (const std::string error = decode(it->second.encoding, std::string_view(data).substr(5), update); !error.empty()) {
    server_->send(c, status(kError, it->second.topic + ": " + error), false);
    return;
  }
  send_update(std::move(update), {c, "", false});
}

void Bridge::send_update(msgs::ParamUpdate update, Request request) {
  const std::string refused = graph::fixed_refusal(boards_, update.name());
  if (!refused.empty()) {
    const msgs::ParamValues::Param* now = graph::find_param(boards_, update.name());
    answer(request, update.name(), parameter(*now), kError, "refused: " + refused);
    return;
  }
  requests_[param_out_->send(std::move(update))] = std::move(request);
  ++stats_.published;
}

void Bridge::get_parameters(net::ClientId c, const json& msg) {
  json list = json::array();
  const json& names = msg.at("parameterNames");
  for (const msgs::ParamValues& b : boards_) {
    for (const msgs::ParamValues::Param& p : b.params()) {
      if (names.empty() || std::find(names.begin(), names.end(), p.name()) != names.end()) list.push_back(parameter(p));
    }
  }
  json values = {{"op", "parameterValues"}, {"parameters", list}};
  if (msg.contains("id")) values["id"] = msg["id"];
  server_->send(c, values.dump(), false);
}

void Bridge::set_parameters(net::ClientId c, const json& msg) {
  const std::string id = msg.value("id", "");
  for (const json& p : msg.at("parameters")) {
    const std::string name = p.at("name").get<std::string>();
    msgs::ParamUpdate update;
    update.set_name(name);
    const Request request{c, id, true};
    if (!param_out_) {
      answer(request, name, json{{"name", name}}, kError, "refused: this bridge is read-only (the graph or the server is reachable from other machines)");
    } else if (!graph::find_param(boards_, name)) {
      answer(request, name, json{{"name", name}}, kError, "refused: " + graph::no_such_param(boards_, name));
    } else if (!p.contains("value") || !set_value(update, p["value"])) {
      answer(request, name, parameter(*graph::find_param(boards_, name)), kError, "refused: a value is a number, a boolean, text or an array");
    } else {
      send_update(std::move(update), request);
    }
  }
}

void Bridge::follow_parameters(Client& client, const json& names, bool follow) {
  if (names.empty()) {
    client.all_param_updates = follow;
    if (!follow) client.param_updates.clear();
  }
  for (const json& n : names) {
    if (follow) client.param_updates.insert(n.get<std::string>());
    else client.param_updates.erase(n.get<std::string>());
  }
}

// the answer to a change a client asked for: a status for both ways (published, set), the
// value in force after it for setParameters with an id
void Bridge::answer(const Request& r, const std::string& name, const json& parameter, int level, const std::string& text) {
  if (!clients_.contains(r.client)) return;
  server_->send(r.client, status(level, name + ": " + text), false);
  if (r.set_parameters && !r.id.empty()) server_->send(r.client, json{{"op", "parameterValues"}, {"parameters", json::array({parameter})}, {"id", r.id}}.dump(), false);
}

// --- observer thread

bool Bridge::run(const std::function<bool()>& stop) {
  bus::RawMessage raw;
  rate_window_start_ns_ = graph_seen_ns_ = rt::now_ns();
  while (!stop()) {
    if (subscriptions_changed_.exchange(false)) update_subscriptions();
    const bool got = sub_->receive(raw, 100);
    const std::int64_t now = rt::now_ns();
    measure_rates(now);
    resend_or_give_up(now);
    if (!follow_graph(now)) return false;
    if (!got) continue;
    const std::string topic(raw.topic());
    const std::string payload(static_cast<const char*>(raw.payload()), raw.payload_size());
    if (topic == bus::kGraphTopic) {
      msgs::GraphInfo info;
      if (info.ParseFromString(payload)) take_graph(info, payload, now);
      continue;
    }
    forward(topic, payload, now);
    if (msgs::ParamValues values; topic.starts_with(graph::kParamValues) && values.ParseFromString(payload)) take_params(values);
    if (msgs::ParamAck ack; topic == graph::kParamAck && ack.ParseFromString(payload)) take_ack(ack);
    if (topic == graph::kSceneState && scene_) {
      msgs::SceneState state;
      ::foxglove::SceneUpdate update;
      if (!state.ParseFromString(payload)) continue;
      scene_->convert(state, update);
      forward(kSceneTopic, update.SerializeAsString(), now);
    }
  }
  return true;
}

void Bridge::take_graph(const msgs::GraphInfo& info, const std::string& payload, std::int64_t now_ns) {
  graph_seen_ns_ = now_ns;
  // the scene, when the graph names a new one
  if (auto named = scene_of(info); named && named != scene_in_use_) {
    scene_in_use_ = std::move(named);
    try {
      scene_.emplace(converter_for(*scene_in_use_));
    } catch (const config::Error& e) {
      std::fprintf(stderr, "enact foxglove: the graph's scene does not load, no foxglove/scene: %s\n", e.what());
    }
  }
  // new topics: a channel each, advertised to every client
  std::vector<std::pair<std::string, std::string>> topics = {{std::string(bus::kGraphTopic), msgs::GraphInfo::descriptor()->full_name()}};
  for (const auto& t : info.topics()) {
    topics.emplace_back(t.name(), t.type());
    if (t.name().starts_with(graph::kParamValues)) sub_->subscribe(t.name());
  }
  if (scene_) topics.emplace_back(kSceneTopic, ::foxglove::SceneUpdate::descriptor()->full_name());
  {
    std::lock_guard lock(mutex_);
    const std::size_t before = channels_.size();
    for (const auto& [name, type] : topics) {
      if (channel_of(name)) continue;
      Channel ch;
      ch.since_ns = now_ns;
      ch.id = ++last_channel_id_;  // never reused: a new graph's channel may differ
      ch.topic = name;
      ch.type = type;
      const bool ours = name == kSceneTopic;
      ch.schema_base64 = base64(ours ? bus::descriptor_set_of(*::foxglove::SceneUpdate::descriptor()) : info.descriptor_set());
      channels_.push_back(std::move(ch));
    }
    if (channels_.size() > before) {
      std::vector<const Channel*> added;
      for (std::size_t i = before; i < channels_.size(); ++i) added.push_back(&channels_[i]);
      const std::string advertise = advertise_json(added);
      for (const auto& [c, client] : clients_) server_->send(c, advertise, false);
    }
  }
  forward(std::string(bus::kGraphTopic), payload, now_ns);
}

void Bridge::forward(const std::string& topic, const std::string& payload, std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  const auto it = std::find_if(channels_.begin(), channels_.end(), [&](const Channel& ch) { return ch.topic == topic; });
  if (it == channels_.end()) return;
  Channel& ch = *it;
  ++ch.window;
  const bool limited = !ch.measured || ch.fast;
  const auto period_ns = static_cast<std::int64_t>(1e9 / options_.max_rate_hz);
  const auto stamp = static_cast<std::uint64_t>(rt::wall_ns());  // Foxglove shows dates
  for (auto& [c, client] : clients_) {
    const auto sub = client.subscription_of.find(ch.id);
    if (sub == client.subscription_of.end()) continue;
    auto& last = client.last_sent_ns[ch.id];
    if (limited && now_ns - last < period_ns) {
      ++stats_.decimated;
      continue;
    }
    // Message Data: opcode, subscription id (u32 LE), timestamp ns (u64 LE), payload
    std::string frame;
    frame.reserve(13 + payload.size());
    frame.push_back(static_cast<char>(kMessageData));
    put_le(frame, sub->second, 4);
    put_le(frame, stamp, 8);
    frame += payload;
    if (server_->send(c, frame, true)) {
      ++stats_.sent;
      last = now_ns;
    } else {
      ++stats_.dropped;
    }
  }
}

void Bridge::update_subscriptions() {
  // what some client wants, plus the scene state behind foxglove/scene
  std::set<std::string> wanted;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [c, client] : clients_) {
      for (const auto& [channel, sub] : client.subscription_of) {
        const auto ch = std::find_if(channels_.begin(), channels_.end(), [id = channel](const Channel& x) { return x.id == id; });
        if (ch == channels_.end()) continue;
        const std::string& topic = ch->topic;
        wanted.insert(topic == kSceneTopic ? std::string(graph::kSceneState) : topic);
      }
    }
  }
  std::erase_if(wanted, received_always);
  for (const std::string& t : zmq_topics_) {
    if (!wanted.contains(t)) sub_->unsubscribe(t);
  }
  // a topic whose messages start to arrive has no measured rate: limited until measured
  const std::int64_t now = rt::now_ns();
  std::lock_guard lock(mutex_);
  for (const std::string& t : wanted) {
    if (zmq_topics_.contains(t)) continue;
    sub_->subscribe(t);
    for (Channel& ch : channels_) {
      if (ch.topic != t && !(t == graph::kSceneState && ch.topic == kSceneTopic)) continue;
      ch.measured = false;
      ch.since_ns = now;
    }
  }
  zmq_topics_ = std::move(wanted);
}

void Bridge::take_params(const msgs::ParamValues& values) {
  std::lock_guard lock(mutex_);
  auto board = std::find_if(boards_.begin(), boards_.end(), [&](const msgs::ParamValues& b) { return b.node() == values.node(); });
  if (board == boards_.end()) board = boards_.insert(boards_.end(), msgs::ParamValues());
  // what changed (or is new), for the clients that follow it
  std::vector<const msgs::ParamValues::Param*> changed;
  for (const msgs::ParamValues::Param& p : values.params()) {
    const auto same = [&](const msgs::ParamValues::Param& b) { return b.name() == p.name() && b.value() == p.value(); };
    if (std::none_of(board->params().begin(), board->params().end(), same)) changed.push_back(&p);
  }
  for (const auto& [c, client] : clients_) {
    json list = json::array();
    for (const msgs::ParamValues::Param* p : changed) {
      if (client.all_param_updates || client.param_updates.contains(p->name())) list.push_back(parameter(*p));
    }
    if (!list.empty()) server_->send(c, json{{"op", "parameterValues"}, {"parameters", list}}.dump(), false);
  }
  *board = values;
}

void Bridge::take_ack(const msgs::ParamAck& ack) {
  std::lock_guard lock(mutex_);
  if (!param_out_) return;
  const auto answered = param_out_->take(ack);
  const auto it = requests_.find(ack.request_id());
  if (!answered || it == requests_.end()) return;
  const msgs::ParamValues::Param* now = graph::find_param(boards_, answered->name);
  json value = now ? parameter(*now) : json{{"name", answered->name}};
  if (ack.value_case() == msgs::ParamAck::kNumber) value["value"] = ack.number();
  if (ack.value_case() == msgs::ParamAck::kText) value["value"] = ack.text();
  answer(it->second, answered->name, value, answered->applied ? kInfo : kError, graph::answer_text(*answered));
  requests_.erase(it);
}

void Bridge::resend_or_give_up(std::int64_t now_ns) {
  std::lock_guard lock(mutex_);
  if (!param_out_) return;
  for (const graph::ParamAnswer& lost : param_out_->tick(now_ns)) {
    const auto it = requests_.find(lost.request_id);
    if (it == requests_.end()) continue;
    const msgs::ParamValues::Param* now = graph::find_param(boards_, lost.name);
    answer(it->second, lost.name, now ? parameter(*now) : json{{"name", lost.name}}, kError, graph::answer_text(lost));
    requests_.erase(it);
  }
}

void Bridge::measure_rates(std::int64_t now_ns) {
  const std::int64_t elapsed = now_ns - rate_window_start_ns_;
  if (elapsed < kRateWindow_ns) return;
  std::lock_guard lock(mutex_);
  for (Channel& ch : channels_) {
    if (ch.since_ns <= rate_window_start_ns_) {
      ch.measured = true;
      ch.fast = ch.fast || static_cast<double>(ch.window) * 1e9 / static_cast<double>(elapsed) > options_.max_rate_hz;
    }
    ch.window = 0;
  }
  rate_window_start_ns_ = now_ns;
}

}  // namespace enact::foxglove

namespace enact::foxglove {

std::string url(const BridgeOptions& options, int port) {
  const bool v6 = options.host.find(':') != std::string::npos;
  return "ws://" + (v6 ? "[" + options.host + "]" : options.host) + ":" + std::to_string(port);
}

std::string describe(const Bridge& bridge, const BridgeOptions& options) {
  return "Foxglove WebSocket server at " + url(options, bridge.port()) + " for the graph at " + options.attach +
         (bridge.client_publish() ? " (clients may set parameters and publish param/set)" : " (read-only: the graph or the server is reachable from other machines)") +
         "\n  open it: Foxglove > Open connection > Foxglove WebSocket > " + url(options, bridge.port()) + "; layout: docs/foxglove-layout.json";
}

std::string format(const BridgeStats& s) {
  char line[200];
  std::snprintf(line, sizeof line, "%llu clients, %llu messages sent, %llu left out by the rate limit, %llu dropped (slow clients), %llu published",
                static_cast<unsigned long long>(s.clients), static_cast<unsigned long long>(s.sent), static_cast<unsigned long long>(s.decimated),
                static_cast<unsigned long long>(s.dropped), static_cast<unsigned long long>(s.published));
  return line;
}

}  // namespace enact::foxglove
