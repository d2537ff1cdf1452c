#pragma once
// The Haply Inverse3 as a ForceDevice (`device: inverse3`), through the Haply Inverse
// Service: a local service that owns the device and speaks JSON over WebSockets
// (protocol.h; Haply's documentation at docs.haply.co). enact builds and runs without it.
//
// configure(): connect to the simulation channel (host:port, default 127.0.0.1:10001), take
// the inventory, pick the Inverse3 (device_id, or the first listed) and refuse one that is
// not ready or in use by another session, each with the fix; connect to the events channel
// (events_port; its absence is said on stderr, not refused). Then an I/O thread runs the
// service's tick loop: send the force command (zero until activate), wait for the one state
// update the service answers with, publish the position and velocity (enact frame: the
// service frame less origin_m) and the first VerseGrip's buttons through the shared
// exchange (core/devices/io_exchange.h). So the loop runs at the rate the service
// answers; the real-time loop never waits on the socket.
// Faults: no answer within reply_timeout_s, or the connection closed (the service stopped,
// the device was unplugged), end the I/O thread: reads say device_error. An event that
// stops the device (device-disconnected, device-busy, an emergency brake) does the same; every
// event is printed to stderr from the events thread and counted.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "core/devices/device.h"
#include "core/devices/inverse3/protocol.h"
#include "core/net/ws_client.h"
#include "core/devices/io_exchange.h"

namespace enact::devices::inverse3 {

struct Inverse3Params {
  std::string host = "127.0.0.1";
  int port = kSimulationPort;                 // the simulation channel
  int events_port = kEventsPort;              // the events channel (0: none)
  std::string device_id;                      // empty: the first Inverse3 the service lists
  math::Vec3 origin_m{0.0, -0.14, 0.14};      // the service-frame point that is enact's origin (TO CHECK: near the workspace centre)
  std::string profile = "inverse3";           // the device profile
  double connect_timeout_s = 2.0;             // (0, 60]: the connection and the inventory
  double reply_timeout_s = 0.1;               // (0, 1]: a service silent this long is lost
  double stale_s = 0.005;                     // (0, 0.009]: a sample older than this is a device error
};

class Inverse3ForceDevice final : public ForceDevice {
 public:
  explicit Inverse3ForceDevice(Inverse3Params params);
  ~Inverse3ForceDevice() override;
  Inverse3ForceDevice(const Inverse3ForceDevice&) = delete;
  Inverse3ForceDevice& operator=(const Inverse3ForceDevice&) = delete;

  void configure() override;
  void activate() override;
  bool read(std::int64_t now_ns, ForceSample& out) noexcept override;
  void write(std::int64_t now_ns, const math::Vec3& force_n) noexcept override;
  void deactivate() noexcept override;
  const devices::DeviceProfile& profile() const override { return profile_; }

  // the device the service gave us
  const std::string& device_id() const { return device_id_; }
  // state updates taken since configure, and events seen
  std::uint64_t updates() const { return updates_.load(); }
  std::uint64_t events() const { return events_.load(); }
  // whether the events channel is connected
  bool events_connected() const { return events_client_ != nullptr; }
  // why the I/O thread stopped ("" while it runs)
  std::string fault() const;

  // how long write() may stay silent before the I/O thread sends zero on its own
  static constexpr double kCommandTimeout_s = 0.020;

 private:
  void close() noexcept;
  void pick_device(const Update& inventory);
  void io_loop() noexcept;
  void events_loop() noexcept;
  void stop_with(const std::string& why) noexcept;

  Inverse3Params params_;
  devices::DeviceProfile profile_;
  std::string device_id_;
  std::unique_ptr<net::WsClient> client_;
  std::unique_ptr<net::WsClient> events_client_;
  IoExchange exchange_;
  std::thread io_;
  std::thread events_thread_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> updates_{0};
  std::atomic<std::uint64_t> events_{0};
  mutable std::mutex fault_mutex_;
  std::string fault_;
  bool configured_ = false;
};

}  // namespace enact::devices::inverse3
