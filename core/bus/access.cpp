#include "core/bus/access.h"

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>
#include <thread>

#include <zmq.h>

#include "core/bus/context.h"
#include "core/bus/keys.h"
#include "core/config/yaml.h"
#include "core/rt/clock.h"

namespace enact::bus {
namespace {


// ZAP (ZeroMQ RFC 27): libzmq asks the handler bound here about every peer of a socket that
// has a security mechanism
constexpr const char* kZapEndpoint = "inproc://zeromq.zap.01";
// how often the ZAP thread looks whether the process is ending
constexpr int kZapPoll_ms = 100;
// a refused key, or a client's dropped messages, are logged at most this often
constexpr std::int64_t kLogPeriod_ns = 60'000'000'000;

// a path of the access file: ~/ is the home folder, a relative one starts at the file's folder
std::string resolve(const std::string& path, const std::string& access_file) {
  if (path.rfind("~/", 0) == 0) {
    const char* home = std::getenv("HOME");
    return std::string(home ? home : "") + path.substr(1);
  }
  if (std::filesystem::path(path).is_absolute()) return path;
  return (std::filesystem::path(access_file).parent_path() / path).string();
}

// a key read from a file named at `key` of `m`; a bad key file is reported at that line
std::string key_from(const config::Map& m, const char* key, bool secret) {
  const std::string path = resolve(m.text(key), m.file());
  try {
    return secret ? read_key_file(path, key) : read_public_key(path, key);
  } catch (const config::Error& e) {
    m.fail(key, e.what(), "fix the key file, or name another");
  }
}

AccessClient client_from(const YAML::Node& node, const std::string& file) {
  const config::Map m(node, file, "client", {"name", "public_key", "public_key_file", "role"});
  AccessClient c;
  c.name = m.text("name");
  if (c.name.empty() || c.name.find_first_of(" \t/:") != std::string::npos) m.fail("name", "client name '" + c.name + "' is not one word", "name the key like its file, e.g. alice-laptop (no spaces, '/' or ':')");
  if (m.has("public_key") == m.has("public_key_file")) {
    m.fail("name", "client '" + c.name + "' needs exactly one of public_key and public_key_file", "give the key inline (public_key: <40 characters>) or its .pub file");
  }
  if (m.has("public_key")) {
    c.public_z85 = m.text("public_key");
    if (!is_z85_key(c.public_z85)) m.fail("public_key", "client '" + c.name + "': public_key is not a key (40 characters of Z85)", "paste the line of its .pub file (`enact keys show FILE`)");
  } else {
    c.public_z85 = key_from(m, "public_key_file", false);
  }
  const std::string role = m.text("role");
  if (role == "observe") c.role = Role::observe;
  else if (role == "operate") c.role = Role::operate;
  else m.fail("role", "client '" + c.name + "': unknown role '" + role + "'", "write role: observe (receive only) or role: operate (also param/set)");
  return c;
}

// one registered domain: the clients allowed, and when each refused key was last logged
struct Domain {
  std::map<std::string, std::string> names;  // public key (32 bytes) -> client name
  LogFn log;
  std::map<std::string, std::int64_t> refused;  // key -> when it was last said (ns)
};

// the process's ZAP handler: one thread, one REP socket, the domains of every CurveServer
class Zap {
 public:
  static Zap& instance() {
    static Zap zap;
    return zap;
  }

  std::string add(const Access& access, LogFn log) {
    const std::lock_guard lock(mutex_);
    const std::string domain = "enact." + std::to_string(next_++);
    Domain& d = domains_[domain];
    for (const AccessClient& c : access.clients) {
      std::string binary(32, '\0');
      zmq_z85_decode(reinterpret_cast<std::uint8_t*>(binary.data()), c.public_z85.c_str());
      d.names[binary] = c.name;
    }
    d.log = std::move(log);
    return domain;
  }

  void remove(const std::string& domain) {
    const std::lock_guard lock(mutex_);
    domains_.erase(domain);
  }

  ~Zap() {
    stop_ = true;
    thread_.join();
  }

 private:
  Zap() : socket_(make_socket(zmq::socket_type::rep)) {
    // bound before any CurveServer exists: libzmq lets every peer in when no handler is bound
    socket_.bind(kZapEndpoint);
    thread_ = std::thread([this] { run(); });
  }

  void run() {
    zmq::pollitem_t item{socket_.handle(), 0, ZMQ_POLLIN, 0};
    while (!stop_) {
      try {
        if (zmq::poll(&item, 1, std::chrono::milliseconds(kZapPoll_ms)) > 0) answer();
      } catch (const zmq::error_t& e) {
        if (e.num() == ETERM) return;
      }
    }
  }

  // one request: version, request id, domain, address, identity, mechanism, credentials
  void answer() {
    const std::vector<std::string> frames = receive_frames(socket_);
    std::string status = "400", text = "unknown key", user;
    if (frames.size() == 7 && frames[0] == "1.0" && frames[5] == "CURVE") user = decide(frames[2], frames[3], frames[6], status, text);
    else if (frames.size() >= 2 && frames[0] == "1.0") text = "only CURVE is accepted";
    // reply: version, request id, status code, status text, user id, metadata
    send_frames(socket_, {"1.0", frames.size() >= 2 ? frames[1] : "", status, text, user, ""});
  }

  // the client's name when its key is allowed in `domain`; else logs the refusal (once a minute per key)
  std::string decide(const std::string& domain, const std::string& address, const std::string& key, std::string& status, std::string& text) {
    const std::lock_guard lock(mutex_);
    const auto d = domains_.find(domain);
    if (d == domains_.end()) return "";
    const auto name = d->second.names.find(key);
    if (name != d->second.names.end()) {
      status = "200";
      text = "OK";
      return name->second;
    }
    char z85[41] = {};
    if (key.size() == 32) zmq_z85_encode(z85, reinterpret_cast<const std::uint8_t*>(key.data()), 32);
    const std::int64_t now = rt::now_ns();
    auto [last, first] = d->second.refused.try_emplace(z85, now);
    if (first || now - last->second >= kLogPeriod_ns) {
      last->second = now;
      if (d->second.log) d->second.log("refused a client key " + fingerprint(z85) + "... from " + address + ": not in the access file (logged once a minute per key)");
    }
    return "";
  }

  std::mutex mutex_;
  std::map<std::string, Domain> domains_;
  unsigned next_ = 0;
  std::atomic<bool> stop_ = false;
  zmq::socket_t socket_;
  std::thread thread_;
};

}  // namespace

const char* to_string(Role role) { return role == Role::operate ? "operate" : "observe"; }

const AccessClient* Access::find(std::string_view name) const {
  for (const AccessClient& c : clients) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

Access load_access(const std::string& path) {
  const YAML::Node root = config::load_file(path);
  const config::Map m(root, path, "access file", {"server_key", "clients", "inbound_rate_per_s"});
  Access a;
  a.file = path;
  a.server_secret_z85 = key_from(m, "server_key", true);
  a.server_public_z85 = public_of(a.server_secret_z85);
  a.inbound_rate_per_s = m.positive("inbound_rate_per_s", a.inbound_rate_per_s);
  const std::vector<YAML::Node> clients = m.list("clients");
  if (clients.empty()) m.fail("clients", "no clients: nobody could attach", "list the keys that may attach under clients: (name, public_key_file, role)");
  std::set<std::string> names, keys;
  for (const YAML::Node& node : clients) {
    AccessClient c = client_from(node, path);
    if (!names.insert(c.name).second) config::fail(path, node, "client name '" + c.name + "' given twice", "give each key its own name");
    if (!keys.insert(c.public_z85).second) config::fail(path, node, "client '" + c.name + "': this public key is listed twice", "list each key once, with the role it needs");
    if (c.public_z85 == a.server_public_z85) config::fail(path, node, "client '" + c.name + "' has the graph's own key", "make the client a key of its own: enact keys new NAME");
    a.clients.push_back(std::move(c));
  }
  return a;
}

OwnClientFiles add_own_client(Access& access, const std::string& dir, const std::string& name) {
  const KeyPair pair = write_key_pair(dir, name);
  access.clients.push_back({name, pair.public_z85, Role::observe});
  OwnClientFiles files{dir + "/" + name + ".key", dir + "/server.pub"};
  std::ofstream(files.server_key) << access.server_public_z85 << "\n";
  return files;
}

CurveServer::CurveServer(zmq::socket_t& socket, const Access& access, LogFn log) : domain_(Zap::instance().add(access, std::move(log))) {
  socket.set(zmq::sockopt::curve_server, true);
  socket.set(zmq::sockopt::curve_secretkey, access.server_secret_z85);
  socket.set(zmq::sockopt::zap_domain, domain_);
}

CurveServer::~CurveServer() { Zap::instance().remove(domain_); }

std::string_view sender_key(const zmq::message_t& frame) {
  const char* user = zmq_msg_gets(const_cast<zmq_msg_t*>(frame.handle()), "User-Id");
  return user ? std::string_view(user) : std::string_view();
}

std::string with_sender_key(std::string_view payload, std::string_view key_name) {
  // Protobuf wire format: a length-delimited field is (number << 3 | 2), a varint length,
  // the bytes; a message field seen twice is merged. Header is field 1, sender_key its 4.
  const auto varint = [](std::string& out, std::size_t v) {
    for (; v >= 0x80; v >>= 7) out.push_back(static_cast<char>((v & 0x7f) | 0x80));
    out.push_back(static_cast<char>(v));
  };
  std::string header;
  header.push_back(static_cast<char>(4 << 3 | 2));
  varint(header, key_name.size());
  header.append(key_name);
  std::string out(payload);
  out.push_back(static_cast<char>(1 << 3 | 2));
  varint(out, header.size());
  out += header;
  return out;
}

InboundGate::InboundGate(const Access& access, LogFn log) : access_(access), log_(std::move(log)) {}

Verdict InboundGate::check(std::string_view key_name, std::int64_t now_ns) {
  const AccessClient* client = access_.find(key_name);
  if (!client) return {false, "no client key", false};
  // a token bucket per client: inbound_rate_per_s tokens a second, one second's worth at most
  Bucket& b = buckets_.try_emplace(client->name, Bucket{access_.inbound_rate_per_s, now_ns}).first->second;
  b.tokens = std::min(access_.inbound_rate_per_s, b.tokens + static_cast<double>(now_ns - b.last_ns) * 1e-9 * access_.inbound_rate_per_s);
  b.last_ns = now_ns;
  if (b.tokens < 1.0) {
    ++dropped_[client->name];
    if (!b.said || now_ns - b.logged_ns >= kLogPeriod_ns) {
      if (log_) {
        log_("dropping inbound messages from key '" + client->name + "' beyond " + std::to_string(static_cast<int>(access_.inbound_rate_per_s)) + " per second: " +
             std::to_string(dropped_[client->name]) + " dropped so far (said again at most once a minute)");
      }
      b.logged_ns = now_ns;
      b.said = true;
    }
    return {false, "over the inbound rate limit", false};
  }
  b.tokens -= 1.0;
  if (client->role != Role::operate) {
    return {false, "key '" + client->name + "' has role observe in " + access_.file + ": only operate keys may change the graph", true};
  }
  return {true, "", false};
}

}  // namespace enact::bus
