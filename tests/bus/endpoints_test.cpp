#include <gtest/gtest.h>

#include <string>

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/bus/endpoints.h"
#include "core/config/yaml.h"

namespace bus = enact::bus;
using enact::config::Error;

namespace {

constexpr const char* kFix = "fix: use ipc://PATH, tcp://HOST:PORT or inproc://NAME";

TEST(Endpoints, BuildersWriteZeroMqEndpoints) {
  EXPECT_EQ(bus::ipc_endpoint("/tmp/g", "ffd"), "ipc:///tmp/g/ffd.sock");
  EXPECT_EQ(bus::inproc_endpoint("sim"), "inproc://sim");
  EXPECT_EQ(bus::tcp_endpoint("127.0.0.1", 5555), "tcp://127.0.0.1:5555");
  EXPECT_EQ(bus::tcp_endpoint("127.0.0.1", 0), "tcp://127.0.0.1:*");
  EXPECT_EQ(bus::tcp_endpoint("::1", 7000), "tcp://[::1]:7000");
}

TEST(Endpoints, ValidOnesPass) {
  for (const char* e : {"ipc:///tmp/x.sock", "inproc://a", "tcp://127.0.0.1:*", "tcp://*:5555", "tcp://[::1]:0",
                        "tcp://localhost:65535"}) {
    EXPECT_NO_THROW(bus::validate_endpoint(e)) << e;
  }
}

TEST(Endpoints, MalformedOnesAreRefusedWithTheFix) {
  for (const char* e : {"", "ipc://", "inproc://", "tcp://127.0.0.1", "tcp://:5555", "tcp://127.0.0.1:65536",
                        "tcp://127.0.0.1:55x", "udp://127.0.0.1:5555", "127.0.0.1:5555", "tcp://127.0.0.1: 5555"}) {
    try {
      bus::validate_endpoint(e, "sim endpoint");
      ADD_FAILURE() << "accepted '" << e << "'";
    } catch (const Error& err) {
      const std::string what = err.what();
      EXPECT_NE(what.find("sim endpoint '" + std::string(e) + "'"), std::string::npos) << what;
      EXPECT_NE(what.find(kFix), std::string::npos) << what;
    }
  }
  EXPECT_THROW(bus::ipc_endpoint("/tmp/" + std::string(120, 'd'), "ffd"), Error);
  EXPECT_THROW(bus::tcp_endpoint("127.0.0.1", 70000), Error);
  EXPECT_THROW(bus::tcp_endpoint("", 1), Error);
}

TEST(Endpoints, LocalOnesAreLoopbackIpcAndInproc) {
  EXPECT_TRUE(bus::is_local("tcp://127.0.0.1:*"));
  EXPECT_TRUE(bus::is_local("tcp://[::1]:5555"));
  EXPECT_TRUE(bus::is_local("tcp://localhost:5555"));
  EXPECT_TRUE(bus::is_local("ipc:///tmp/x"));
  EXPECT_TRUE(bus::is_local("inproc://x"));
  EXPECT_FALSE(bus::is_local("tcp://*:5555"));
  EXPECT_FALSE(bus::is_local("tcp://0.0.0.0:5555"));
  EXPECT_FALSE(bus::is_local("tcp://192.168.1.10:5555"));
}

TEST(Endpoints, AttachPointRefusesAnExposedEndpointUnlessAllowed) {
  try {
    bus::AttachPoint ap("g", {.bind_endpoint = "tcp://0.0.0.0:*"});
    ADD_FAILURE() << "bound an exposed endpoint";
  } catch (const Error& err) {
    EXPECT_NE(std::string(err.what()).find("allow_remote"), std::string::npos) << err.what();
  }
}

TEST(Endpoints, BindingAPortInUseIsAConfigError) {
  const bus::BytePublisher first("tcp://127.0.0.1:*");
  EXPECT_THROW(bus::BytePublisher second(first.endpoint()), Error);
  EXPECT_THROW(bus::BytePublisher bad("tcp://127.0.0.1:*", {.node = "ffd", .send_hwm = 0}), Error);
}

}  // namespace
