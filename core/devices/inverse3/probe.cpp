#include "core/devices/inverse3/probe.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "core/devices/inverse3/protocol.h"
#include "core/net/ws_client.h"

namespace enact::devices::inverse3 {

vendor::Presence probe_inverse3(const std::string& host, int port, double timeout_s) {
  const std::string what = "Haply Inverse3 (device: inverse3): ";
  const std::string where = host + ":" + std::to_string(port);
  std::optional<std::string> inventory;
  try {
    net::WsClient client(host, port, timeout_s);
    inventory = client.receive(std::llround(timeout_s * 1e9));
  } catch (const std::runtime_error& e) {
    return {false, what + "absent: the Haply Inverse Service does not answer on " + where + " (" + e.what() + ")\n" +
                       "  fix: install and start the service (the Haply Hub, or: systemctl start haply-inverse-service); if it listens elsewhere, --inverse3-port N\n"};
  }
  Update u;
  std::string why = "nothing received";
  if (!inventory || !parse_update(*inventory, u, why)) {
    return {false, what + "the service on " + where + " sent no inventory (" + why + ")\n  fix: --inverse3-port must be its simulation channel (default 10001)\n"};
  }
  if (u.inverse3.empty()) return {false, what + "the service on " + where + " lists no Inverse3\n  fix: plug the Inverse3 in and power it on\n"};
  vendor::Presence out;
  for (const DeviceEntry& d : u.inverse3) {
    const bool usable = d.ready && !d.in_use;
    out.present = out.present || usable;
    out.report += what + d.device_id + " on the service at " + where + "  " + (d.in_use ? "in use by another session" : d.ready ? "ready (launch/bridge_rt_inverse3.yaml)" : "not ready") + "\n";
  }
  return out;
}

}  // namespace enact::devices::inverse3
