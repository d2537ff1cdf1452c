#pragma once
// Endpoints of bus sockets: building them, and refusing malformed ones at load time.
//   ipc://PATH       a Unix socket file, for processes on this machine (PATH <= 107 bytes)
//   tcp://HOST:PORT  HOST an IPv4 address, [IPv6], host or interface name, or * (bind on every
//                    interface); PORT 1-65535, or * (or 0) to bind any free port, read back with
//                    BytePublisher::endpoint() / AttachPoint::endpoint()
//   inproc://NAME    between sockets of one process
#include <string>

namespace enact::bus {

// loopback, any free port: the default bind of an attach point
inline constexpr const char* kLoopbackAnyPort = "tcp://127.0.0.1:*";

// "ipc://DIR/NODE.sock"; throws config::Error if the path is too long for a Unix socket
std::string ipc_endpoint(const std::string& dir, const std::string& node);

// "inproc://NAME"; throws config::Error if NAME is empty
std::string inproc_endpoint(const std::string& name);

// "tcp://HOST:PORT", IPv6 addresses in brackets; port 0 gives "tcp://HOST:*" (bind any free
// port); throws config::Error if HOST is empty or PORT is outside 0-65535
std::string tcp_endpoint(const std::string& host, int port);

// throws config::Error when `endpoint` is malformed, naming it (`what`, e.g. "attach
// endpoint"), the problem and the fix; a valid endpoint may still fail to bind (port in use)
void validate_endpoint(const std::string& endpoint, const std::string& what = "endpoint");

// true when only this machine can reach the endpoint: ipc://, inproc://, and tcp:// on a
// loopback host (127.x.x.x, [::1], localhost, lo)
bool is_local(const std::string& endpoint);

}  // namespace enact::bus
