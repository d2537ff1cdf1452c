#include "core/bus/endpoints.h"

#include <cctype>
#include <string_view>

#include "core/config/yaml.h"

namespace enact::bus {
namespace {

// sockaddr_un.sun_path holds 108 bytes with the terminating zero
constexpr std::size_t kMaxIpcPath = 107;

constexpr std::string_view kIpc = "ipc://";
constexpr std::string_view kTcp = "tcp://";
constexpr std::string_view kInproc = "inproc://";

[[noreturn]] void refuse(const std::string& what, const std::string& endpoint, const std::string& problem) {
  throw config::Error(what + " '" + endpoint + "': " + problem +
                      "\n  fix: use ipc://PATH, tcp://HOST:PORT or inproc://NAME");
}

bool has_space(std::string_view s) {
  for (const char c : s) {
    if (std::isspace(static_cast<unsigned char>(c))) return true;
  }
  return false;
}

// "*", or a whole number from 0 to 65535
bool valid_port(std::string_view port) {
  if (port == "*") return true;
  if (port.empty() || port.size() > 5) return false;
  int value = 0;
  for (const char c : port) {
    if (c < '0' || c > '9') return false;
    value = value * 10 + (c - '0');
  }
  return value <= 65535;
}

// the HOST of tcp://HOST:PORT, without IPv6 brackets (empty if malformed)
std::string_view tcp_host(std::string_view rest) {
  const std::size_t colon = rest.rfind(':');
  if (colon == std::string_view::npos) return {};
  std::string_view host = rest.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  return host;
}

}  // namespace

std::string ipc_endpoint(const std::string& dir, const std::string& node) {
  const std::string endpoint = std::string(kIpc) + dir + "/" + node + ".sock";
  validate_endpoint(endpoint, "ipc endpoint of node '" + node + "'");
  return endpoint;
}

std::string inproc_endpoint(const std::string& name) {
  const std::string endpoint = std::string(kInproc) + name;
  validate_endpoint(endpoint, "inproc endpoint");
  return endpoint;
}

std::string tcp_endpoint(const std::string& host, int port) {
  if (port < 0 || port > 65535) {
    refuse("tcp endpoint", host + ":" + std::to_string(port), "the port must be from 0 (any free port) to 65535");
  }
  const bool ipv6 = !host.empty() && host.find(':') != std::string::npos && host.front() != '[';
  const std::string endpoint = std::string(kTcp) + (ipv6 ? "[" + host + "]" : host) + ":" +
                               (port == 0 ? std::string("*") : std::to_string(port));
  validate_endpoint(endpoint, "tcp endpoint");
  return endpoint;
}

void validate_endpoint(const std::string& endpoint, const std::string& what) {
  const std::string_view e = endpoint;
  if (has_space(e)) refuse(what, endpoint, "an endpoint has no spaces");
  if (e.starts_with(kIpc)) {
    const std::string_view path = e.substr(kIpc.size());
    if (path.empty()) refuse(what, endpoint, "the ipc path is empty");
    if (path.size() > kMaxIpcPath) {
      refuse(what, endpoint, "the ipc path is " + std::to_string(path.size()) + " bytes, more than a Unix socket takes (" +
                                 std::to_string(kMaxIpcPath) + "); use a shorter directory");
    }
  } else if (e.starts_with(kInproc)) {
    if (e.size() == kInproc.size()) refuse(what, endpoint, "the inproc name is empty");
  } else if (e.starts_with(kTcp)) {
    const std::string_view rest = e.substr(kTcp.size());
    const std::size_t colon = rest.rfind(':');
    if (colon == std::string_view::npos) refuse(what, endpoint, "no :PORT after the host");
    if (tcp_host(rest).empty()) refuse(what, endpoint, "the host is empty");
    if (!valid_port(rest.substr(colon + 1))) refuse(what, endpoint, "the port must be * or a number from 0 to 65535");
  } else {
    refuse(what, endpoint, "unknown transport");
  }
}

bool is_local(const std::string& endpoint) {
  const std::string_view e = endpoint;
  if (e.starts_with(kIpc) || e.starts_with(kInproc)) return true;
  if (!e.starts_with(kTcp)) return false;
  const std::string_view host = tcp_host(e.substr(kTcp.size()));
  return host.starts_with("127.") || host == "::1" || host == "localhost" || host == "lo";
}

}  // namespace enact::bus
