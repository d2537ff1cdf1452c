#include "core/foxglove/bridge.h"

#include <chrono>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "core/bus/endpoints.h"
#include "core/bus/schema.h"
#include "core/config/yaml.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"
#include "msgs/param_update.pb.h"

namespace enact::foxglove {
namespace {

using nlohmann::json;

constexpr std::uint8_t kMessageData = 0x01;  // binary opcode, both directions
constexpr std::int64_t kRateWindow_ns = 200'000'000;  // a loop-rate topic is limited within 0.2 s

// the wall clock in ns: Foxglove shows message times as dates
std::uint64_t wall_ns() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count());
}

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
  // client publishing only where nobody from another machine can reach either side
  if (bus::is_local(options_.attach) && loopback_host(options_.host)) sender_ = std::make_unique<bus::AttachSender>(options_.attach, "foxglove", options_.keys);
  sub_.set_receive_hwm(100'000);
  bus::attach_connect(sub_.socket(), options_.attach, options_.keys);
  sub_.subscribe(std::string(bus::kGraphTopic));
  WsHandlers h;
  h.on_open = [this](ClientId c) { on_open(c); };
  h.on_close = [this](ClientId c) { on_close(c); };
  h.on_text = [this](ClientId c, const std::string& t) { on_text(c, t); };
  h.on_binary = [this](ClientId c, const std::string& d) { on_binary(c, d); };
  try {
    server_ = std::make_unique<WsServer>(options_.host, options_.port, kSubprotocol, std::move(h), options_.max_backlog_bytes);
  } catch (const std::runtime_error& e) {
    throw config::Error(std::string(e.what()) + "\n  fix: give a free port with --port, or stop what uses it");
  }
}

Bridge::~Bridge() { server_->stop(); }

int Bridge::port() const { return server_->port(); }

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

void Bridge::on_open(ClientId c) {
  json info = {{"op", "serverInfo"},
               {"name", "enact"},
               {"capabilities", sender_ ? json::array({"clientPublish"}) : json::array()},
               {"metadata", {{"graph", options_.attach}, {"maxRateHz", std::to_string(options_.max_rate_hz)}}},
               {"sessionId", std::to_string(wall_ns())}};
  if (sender_) info["supportedEncodings"] = json::array({"protobuf"});
  std::lock_guard lock(mutex_);
  clients_[c];
  server_->send(c, info.dump(), false);
  std::vector<const Channel*> all;
  for (const Channel& ch : channels_) all.push_back(&ch);
  if (!all.empty()) server_->send(c, advertise_json(all), false);
}

void Bridge::on_close(ClientId c) {
  std::lock_guard lock(mutex_);
  clients_.erase(c);
  subscriptions_changed_ = true;
}

void Bridge::on_text(ClientId c, const std::string& text) {
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
    } else if (op == "advertise" && sender_) {
      for (const json& ch : msg.at("channels")) {
        const std::string topic = ch.at("topic").get<std::string>();
        if (topic.ends_with(graph::kParamSet) && ch.value("schemaName", "") == msgs::ParamUpdate::descriptor()->full_name()) {
          client.published_topic[ch.at("id").get<std::uint32_t>()] = graph::kParamSet;
        } else {
          server_->send(c, status(2, "only param/set (enact.msgs.ParamUpdate, protobuf) may be published, not " + topic), false);
        }
      }
    } else if (op == "unadvertise" && sender_) {
      for (const json& id : msg.at("channelIds")) client.published_topic.erase(id.get<std::uint32_t>());
    } else {
      server_->send(c, status(1, "unsupported operation '" + op + "'"), false);
    }
  } catch (const json::exception& e) {
    server_->send(c, status(2, "malformed '" + op + "' message: " + e.what()), false);
  }
}

void Bridge::on_binary(ClientId c, const std::string& data) {
  if (!sender_ || data.size() < 5 || static_cast<std::uint8_t>(data[0]) != kMessageData) return;
  std::lock_guard lock(mutex_);
  const auto& published = clients_[c].published_topic;
  const auto it = published.find(get_le32(data, 1));
  msgs::ParamUpdate update;
  if (it == published.end() || !update.ParseFromArray(data.data() + 5, static_cast<int>(data.size() - 5))) {
    server_->send(c, status(2, "message on a channel not advertised, or not a ParamUpdate"), false);
    return;
  }
  if (sender_->send(it->second, update)) ++stats_.published;
}

// --- observer thread

void Bridge::run(const std::function<bool()>& stop) {
  bus::RawMessage raw;
  rate_window_start_ns_ = rt::now_ns();
  while (!stop()) {
    if (subscriptions_changed_.exchange(false)) update_subscriptions();
    const bool got = sub_.receive(raw, 100);
    const std::int64_t now = rt::now_ns();
    measure_rates(now);
    if (!got) continue;
    const std::string topic(raw.topic());
    const std::string payload(static_cast<const char*>(raw.payload()), raw.payload_size());
    if (topic == bus::kGraphTopic) {
      msgs::GraphInfo info;
      if (info.ParseFromString(payload)) take_graph(info, payload, now);
      continue;
    }
    forward(topic, payload, now);
    if (topic == graph::kSceneState && scene_) {
      msgs::SceneState state;
      ::foxglove::SceneUpdate update;
      if (!state.ParseFromString(payload)) continue;
      scene_->convert(state, update);
      forward(kSceneTopic, update.SerializeAsString(), now);
    }
  }
}

void Bridge::take_graph(const msgs::GraphInfo& info, const std::string& payload, std::int64_t now_ns) {
  // the scene, when the graph names a new one
  if (const auto text = scene_text(info); text && *text != scene_text_) {
    scene_text_ = *text;
    try {
      scene_.emplace(converter_for(*text));
    } catch (const config::Error& e) {
      std::fprintf(stderr, "enact foxglove: the graph's scene does not load, no foxglove/scene: %s\n", e.what());
    }
  }
  // new topics: a channel each, advertised to every client
  std::vector<std::pair<std::string, std::string>> topics = {{std::string(bus::kGraphTopic), msgs::GraphInfo::descriptor()->full_name()}};
  for (const auto& t : info.topics()) topics.emplace_back(t.name(), t.type());
  if (scene_) topics.emplace_back(kSceneTopic, ::foxglove::SceneUpdate::descriptor()->full_name());
  {
    std::lock_guard lock(mutex_);
    const std::size_t before = channels_.size();
    for (const auto& [name, type] : topics) {
      if (channel_of(name)) continue;
      Channel ch;
      ch.id = static_cast<std::uint32_t>(channels_.size() + 1);
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
  const bool limited = ch.rate_hz > options_.max_rate_hz;
  const auto period_ns = static_cast<std::int64_t>(1e9 / options_.max_rate_hz);
  const std::uint64_t stamp = wall_ns();
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
        const std::string& topic = channels_[channel - 1].topic;
        wanted.insert(topic == kSceneTopic ? std::string(graph::kSceneState) : topic);
      }
    }
  }
  wanted.erase(std::string(bus::kGraphTopic));
  for (const std::string& t : zmq_topics_) {
    if (!wanted.contains(t)) sub_.unsubscribe(t);
  }
  for (const std::string& t : wanted) {
    if (!zmq_topics_.contains(t)) sub_.subscribe(t);
  }
  zmq_topics_ = std::move(wanted);
}

void Bridge::measure_rates(std::int64_t now_ns) {
  const std::int64_t elapsed = now_ns - rate_window_start_ns_;
  if (elapsed < kRateWindow_ns) return;
  std::lock_guard lock(mutex_);
  for (Channel& ch : channels_) {
    ch.rate_hz = static_cast<double>(ch.window) * 1e9 / static_cast<double>(elapsed);
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
         (bridge.client_publish() ? " (clients may publish param/set)" : " (read-only: the graph or the server is reachable from other machines)") +
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
