#pragma once
// Helpers for the bus tests: endpoints per transport, bounded waits, sample messages.
#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "core/bus/endpoints.h"
#include "msgs/device_state.pb.h"
#include "tests/support/test_util.h"

namespace enact::test {

// generous bound for anything asynchronous (the machine is noisy; nothing here is timed)
constexpr int kWait_ms = 2000;

// a fresh endpoint to bind on `transport` ("inproc", "ipc" or "tcp")
inline std::string bind_endpoint(const std::string& transport, const TempDir& dir) {
  static std::atomic<int> next = 0;
  const std::string name = "bus-test-" + std::to_string(next++);
  if (transport == "inproc") return bus::inproc_endpoint(name);
  if (transport == "ipc") return bus::ipc_endpoint(dir.path(), name);
  return bus::tcp_endpoint("127.0.0.1", 0);
}

// a DeviceState with every field set; header left to the publisher
inline msgs::DeviceState sample_state(double x) {
  msgs::DeviceState m;
  m.mutable_position()->set_x(x);
  m.mutable_position()->set_y(-0.003);
  m.mutable_position()->set_z(0.0205);
  m.mutable_velocity()->set_x(0.5);
  m.mutable_velocity()->set_y(-1.25);
  m.mutable_velocity()->set_z(0.001);
  m.set_buttons(0b101);
  m.set_faults(msgs::DEVICE_FAULT_WATCHDOG);
  return m;
}

}  // namespace enact::test
