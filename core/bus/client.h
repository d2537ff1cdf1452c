#pragma once
// How a tool attaches to a graph's attach point: every observer and sender (enact topic,
// param, record, the logger, the viewer, bridges) connects its sockets through
// attach_connect, plain on a graph without an access file, as a CURVE client with its keys
// on one with (core/bus/access.h). A failed handshake is said, not silently retried.
#include <string>

#include <zmq.hpp>

namespace enact::bus {

// a client's keys; all empty: no CURVE
struct ClientKeys {
  std::string secret_z85;
  std::string public_z85;
  std::string server_public_z85;  // the graph's public key
  bool enabled() const { return !server_public_z85.empty(); }
};

// the keys of --key FILE.key (the client's secret key) and --server-key FILE.pub (the graph's
// public key); an empty argument falls back to $ENACT_KEY / $ENACT_SERVER_KEY. Neither given:
// no keys. Throws config::Error when only one of the two is given or a file is not a key.
ClientKeys client_keys(const std::string& key_file, const std::string& server_key_file);

// how long attach_connect waits for the handshake by default, ms
inline constexpr int kHandshakeWait_ms = 3000;

// connects `socket` (SUB or XSUB, not connected yet) to the attach point at `endpoint`, with
// `keys` as a CURVE client when enabled, then waits up to `wait_ms` for the handshake. Throws
// config::Error saying why and what to do when the graph refused the key, the handshake failed
// (a wrong --server-key), or one side has keys and the other none. Returns when the handshake
// succeeded, when nothing listens at `endpoint` yet, or after `wait_ms` (ZeroMQ keeps
// retrying: a graph that starts later is attached to).
void attach_connect(zmq::socket_t& socket, const std::string& endpoint, const ClientKeys& keys, int wait_ms = kHandshakeWait_ms);

}  // namespace enact::bus
