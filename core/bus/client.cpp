#include "core/bus/client.h"

#include <chrono>
#include <cstdlib>
#include <cstring>

#include <zmq.h>

#include "core/config/env.h"
#include "core/bus/context.h"
#include "core/bus/endpoints.h"
#include "core/bus/keys.h"
#include "core/config/yaml.h"
#include "core/rt/clock.h"

namespace enact::bus {
namespace {

// `option` if given, else the environment variable `env`, else ""
std::string option_or_env(const std::string& option, const char* env) {
  if (!option.empty()) return option;
  const char* value = std::getenv(env);
  return value ? value : "";
}

// the events of one connection attempt that decide it
constexpr int kEvents = ZMQ_EVENT_HANDSHAKE_SUCCEEDED | ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL | ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL |
                        ZMQ_EVENT_HANDSHAKE_FAILED_AUTH | ZMQ_EVENT_DISCONNECTED | ZMQ_EVENT_CONNECT_RETRIED;

// what a monitor event means for the attach, "" when it succeeded, nullopt-like "?" to go on
std::string explain(int event, int value, const std::string& endpoint, bool keyed) {
  const std::string where = "attach point " + endpoint + ": ";
  switch (event) {
    case ZMQ_EVENT_HANDSHAKE_SUCCEEDED:
      return "";
    case ZMQ_EVENT_HANDSHAKE_FAILED_AUTH:
      return where + "the graph refused this key (status " + std::to_string(value) + ")\n  fix: ask the graph's operator to add your public key (enact keys show YOUR.key) to its access file";
    case ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL:
      if (value == ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH) {
        return keyed ? where + "the graph does not use keys (launched without --access)\n  fix: attach without --key and --server-key"
                     : where + "the graph requires keys (launched with --access)\n  fix: give --key YOUR.key and --server-key GRAPH.pub";
      }
      [[fallthrough]];
    default:
      return keyed ? where + "the CURVE handshake failed: --server-key is not this graph's public key, or the graph refused the key\n  fix: give the .pub file of the key named server_key in the graph's access file"
                   : where + "the handshake failed: the graph requires keys (launched with --access)\n  fix: give --key YOUR.key and --server-key GRAPH.pub";
  }
}

}  // namespace

ClientKeys client_keys(const std::string& key_file, const std::string& server_key_file) {
  const std::string key = option_or_env(key_file, env::kKey);
  const std::string server = option_or_env(server_key_file, env::kServerKey);
  if (key.empty() && server.empty()) return {};
  if (key.empty() || server.empty()) {
    throw config::Error(std::string("keys: ") + (key.empty() ? "--server-key given without --key" : "--key given without --server-key") +
                        "\n  fix: give both: --key YOUR.key (your secret key) and --server-key GRAPH.pub (the graph's public key)");
  }
  ClientKeys k;
  k.secret_z85 = read_key_file(key, "--key");
  k.public_z85 = public_of(k.secret_z85);
  k.server_public_z85 = read_public_key(server, "--server-key");
  return k;
}

void attach_connect(zmq::socket_t& socket, const std::string& endpoint, const ClientKeys& keys, int wait_ms) {
  validate_endpoint(endpoint, "attach endpoint");
  if (keys.enabled()) {
    socket.set(zmq::sockopt::curve_serverkey, keys.server_public_z85);
    socket.set(zmq::sockopt::curve_publickey, keys.public_z85);
    socket.set(zmq::sockopt::curve_secretkey, keys.secret_z85);
  }
  // a monitor on the socket tells how the first connection attempt ends
  const std::string monitor = monitor_endpoint();
  if (zmq_socket_monitor(socket.handle(), monitor.c_str(), kEvents) != 0) throw zmq::error_t();
  zmq::socket_t events(context(), zmq::socket_type::pair);
  events.set(zmq::sockopt::linger, 0);
  events.connect(monitor);
  socket.connect(endpoint);
  std::string failure;
  const std::int64_t end_ns = rt::now_ns() + std::int64_t{wait_ms} * 1'000'000;
  for (;;) {
    const int left = rt::ms_until(end_ns);
    if (left <= 0) break;
    events.set(zmq::sockopt::rcvtimeo, static_cast<int>(left));
    // an event: [uint16 event, uint32 value] then the endpoint
    zmq::message_t head, address;
    const Received got = recv_frame(events, head, zmq::recv_flags::none);
    if (got == Received::interrupted) continue;
    if (got == Received::none || head.size() < 6 || !head.more()) break;
    recv_more(events, address);
    std::uint16_t event = 0;
    std::uint32_t value = 0;
    std::memcpy(&event, head.data(), 2);
    std::memcpy(&value, static_cast<const char*>(head.data()) + 2, 4);
    // nothing listens yet: ZeroMQ retries, the tool waits for the graph in its own way
    if (event == ZMQ_EVENT_CONNECT_RETRIED) break;
    // a peer that closes before any handshake event refused our hello (the wrong server key)
    failure = explain(event, value, endpoint, keys.enabled());
    break;
  }
  (void)zmq_socket_monitor(socket.handle(), nullptr, 0);
  if (!failure.empty()) throw config::Error(failure);
}

}  // namespace enact::bus
