#pragma once
// Who may attach to a graph and what they may do: the access file (YAML, `enact launch FILE
// --access ACCESS.yaml`, format in launch/access.example.yaml), the ZAP handler that lets
// only its clients' keys through a CURVE socket (ZeroMQ RFC 27), and the gate that decides,
// per inbound message, from the key that sent it: role, rate limit, audit stamp.
//
// Roles: `observe` receives every topic; `operate` also sends on inbound topics (param/set).
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <zmq.hpp>

namespace enact::bus {

enum class Role { observe, operate };

// "observe" / "operate"
const char* to_string(Role role);

struct AccessClient {
  std::string name;        // the key's name: logs, audit stamps (header.sender_key)
  std::string public_z85;  // its public key
  Role role = Role::observe;
};

struct Access {
  std::string file;               // where it was read
  std::string server_secret_z85;  // the graph's secret key
  std::string server_public_z85;  // and its public key (what clients give as --server-key)
  std::vector<AccessClient> clients;
  double inbound_rate_per_s = 100.0;  // per client; beyond it inbound messages are dropped

  // the client named `name`, or nullptr
  const AccessClient* find(std::string_view name) const;
};

// reads an access file; throws config::Error naming the file, the line and the fix (unknown
// key, bad role, a key that is not one, a name or key given twice, a server key file others
// can read). Key file paths are relative to the access file's folder; ~/ is the home folder.
Access load_access(const std::string& path);

// the key files of a graph's own observers (enact-logger in its launch file)
struct OwnClientFiles {
  std::string key;         // its secret key, for $ENACT_KEY
  std::string server_key;  // the graph's public key, for $ENACT_SERVER_KEY
};

// gives the graph's own observers a key: a fresh pair in `dir` (a private folder), listed in
// `access` as client `name`, role observe, and the graph's public key beside it
OwnClientFiles add_own_client(Access& access, const std::string& dir, const std::string& name);

// where messages for people go (the launcher's log: stderr)
using LogFn = std::function<void(const std::string&)>;

// makes `socket` a CURVE server with the access file's server key, its peers checked by the
// process's ZAP handler against `access`'s clients (a peer whose key is not there gets no
// connection; the ZAP User-Id of an accepted one is its client name). Refused keys are
// logged through `log`, at most once per key per minute. Call before bind(); the returned
// registration must outlive the socket's connections.
class CurveServer {
 public:
  CurveServer(zmq::socket_t& socket, const Access& access, LogFn log);
  ~CurveServer();
  CurveServer(const CurveServer&) = delete;
  CurveServer& operator=(const CurveServer&) = delete;

 private:
  std::string domain_;
};

// the name of the key that sent `frame` through a CURVE server socket ("" on a socket
// without one)
std::string_view sender_key(const zmq::message_t& frame);

// `payload` (a bus message: Header header = 1) with header.sender_key set to `key_name`:
// one more header field appended, which Protobuf merges into the header, overriding any value
// the sender put there
std::string with_sender_key(std::string_view payload, std::string_view key_name);

// the decision on one inbound message
struct Verdict {
  bool pass = false;
  std::string reason;  // why not (empty when it passes)
  bool answer = false; // refused (role): tell the sender; dropped (rate): silently
};

// the inbound policy of an attach point with an access file: operators' messages pass,
// observers' are refused with the reason, each client's beyond inbound_rate_per_s (a burst
// of one second's worth) are dropped, counted and logged at most once per minute
class InboundGate {
 public:
  InboundGate(const Access& access, LogFn log);

  // the verdict on a message from the key named `key_name` (sender_key) at `now`
  Verdict check(std::string_view key_name, std::int64_t now_ns);

  // messages dropped by the rate limit, per client name
  const std::map<std::string, std::uint64_t, std::less<>>& dropped() const { return dropped_; }

 private:
  struct Bucket {
    double tokens = 0.0;
    std::int64_t last_ns = 0;
    std::int64_t logged_ns = 0;  // when a drop was last said
    bool said = false;           // a drop said at all
  };

  const Access& access_;
  LogFn log_;
  std::map<std::string, Bucket, std::less<>> buckets_;
  std::map<std::string, std::uint64_t, std::less<>> dropped_;
};

}  // namespace enact::bus
