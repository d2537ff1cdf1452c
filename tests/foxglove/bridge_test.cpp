// Foxglove's own WebSocket client (npm @foxglove/ws-protocol, installed by scripts/setup.sh
// into .deps/npm; tests/interop/foxglove_client.mjs) against `enact foxglove` attached to the
// co-located bridge graph: every topic of the graph advertised with a schema protobufjs
// decodes, the scene arriving as foxglove.SceneUpdate, loop-rate topics limited per client,
// param/set published by the client and answered.
#include <signal.h>

#include <filesystem>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/record/reader.h"
#include "msgs/foxglove/scene_update.pb.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

const std::string kModules = std::string(ENACT_SOURCE_DIR) + "/.deps/npm/node_modules";

class FoxgloveBridge : public ::testing::Test {
 protected:
  void SetUp() override {
    if (run("command -v node").exit_code != 0) GTEST_SKIP() << "Node.js is absent: Foxglove's client (@foxglove/ws-protocol) cannot run";
    ASSERT_TRUE(std::filesystem::exists(kModules + "/@foxglove/ws-protocol")) << "@foxglove/ws-protocol is missing from .deps/npm: run scripts/setup.sh";
  }
};

TEST_F(FoxgloveBridge, FoxglovesClientSeesEveryTopicDecodesItAndGetsTheScene) {
  TempDir dir;
  Launcher graph(dir, source_path("launch/bridge_rt.yaml"), 30.0);
  ASSERT_TRUE(graph.wait_log("enact launch: graph ready", 30.0)) << graph.log();
  const int port = free_port();
  const pid_t bridge = spawn({ENACT_CLI, "foxglove", "--port", std::to_string(port), "--max-rate", "50", "--attach", graph.endpoint()},
                             dir.file("bridge.out"), dir.file("bridge.err"));
  // the server listens at once; the client retries nothing, so wait for its line
  const auto until = after(10.0);
  const auto bridge_log = [&] { return std::filesystem::exists(dir.file("bridge.err")) ? read_file(dir.file("bridge.err")) : std::string(); };
  while (bridge_log().find("ws://") == std::string::npos && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const RunResult client = run("ENACT_NODE_MODULES=" + kModules + " node " + source_path("tests/interop/foxglove_client.mjs") + " ws://127.0.0.1:" +
                               std::to_string(port) + " 6");
  kill(bridge, SIGTERM);
  int status = 0;
  waitpid(bridge, &status, 0);
  ASSERT_EQ(client.exit_code, 0) << client.err << bridge_log();
  const nlohmann::json s = nlohmann::json::parse(client.out);

  // every topic the graph lists is advertised, each with a schema protobufjs decoded
  ASSERT_FALSE(s["graph_topics"].empty()) << client.out;
  for (const auto& topic : s["graph_topics"]) EXPECT_TRUE(s["channels"].contains(topic.get<std::string>())) << topic;
  EXPECT_EQ(s["channels"]["ffd/state"]["schema"], "enact.msgs.DeviceState");
  EXPECT_EQ(s["channels"]["foxglove/scene"]["schema"], "foxglove.SceneUpdate");
  for (const char* topic : {"ffd/state", "ffd/force", "sim/scene", "tactile/frame", "node/status"}) EXPECT_GT(s["received"][topic]["count"], 0) << topic;

  // the scene: the bridge's boxes and the floor, the 4 x 4 grid, red where in contact, the force arrow
  ASSERT_GT(s["received"]["foxglove/scene"]["count"], 0) << client.out;
  for (const auto& e : s["scene"]) {
    EXPECT_EQ(e["frame"], "scene");
    if (e["id"] == "bridge") EXPECT_GE(e["cubes"].get<int>(), 4);
    if (e["id"] == "body") EXPECT_EQ(e["spheres"], 16);
  }
  EXPECT_GT(s["most_red_spheres"].get<int>(), 0) << "no mass ever shown in contact";
  EXPECT_GT(s["scenes_with_arrow"].get<int>(), 0) << "no force arrow";

  // the 5 kHz topics reach this client at about --max-rate (50 Hz), not at the loop rate
  const double state_hz = s["received"]["ffd/state"]["steady_rate_hz"];
  EXPECT_GT(state_hz, 10.0);
  EXPECT_LE(state_hz, 55.0);
  EXPECT_EQ(s["channels"]["ffd/state"]["max_rate_hz"], 50);

  // the client's param/set reached the simulator, which answered on param/ack
  EXPECT_EQ(s["capabilities"], nlohmann::json::array({"clientPublish"}));
  ASSERT_TRUE(s["ack"].is_object()) << client.out;
  EXPECT_TRUE(s["ack"]["applied"].get<bool>()) << s["ack"]["reason"];
}

// a recording of the graph gets foxglove/scene: one SceneUpdate per sim/scene, at its log time,
// which the independent MCAP reader (@mcap/core + protobufjs) decodes with the stored schema
TEST_F(FoxgloveBridge, ExportAddsTheSceneToARecording) {
  TempDir dir;
  const std::string file = dir.file("run.mcap"), out = dir.file("run_foxglove.mcap");
  {
    Launcher graph(dir, source_path("launch/bridge_rt.yaml"), 30.0, {"observers=1"});
    ASSERT_TRUE(graph.wait_log("started rt", 15.0)) << graph.log();
    const RunResult rec = run(std::string(ENACT_CLI) + " record -o " + file + " --attach " + graph.endpoint() + " --duration 2");
    ASSERT_EQ(rec.exit_code, 0) << rec.err;
  }
  const RunResult exp = run(std::string(ENACT_CLI) + " export " + file + " --foxglove " + out);
  ASSERT_EQ(exp.exit_code, 0) << exp.err;
  std::map<std::int64_t, int> scene_times;
  int updates = 0, red = 0;
  record::Reader r(out);
  r.for_each([&](const record::Message& m) {
    if (m.topic == "sim/scene") ++scene_times[m.log_time_ns];
    if (m.topic != "foxglove/scene") return true;
    ::foxglove::SceneUpdate u;
    EXPECT_TRUE(u.ParseFromArray(m.data.data(), static_cast<int>(m.data.size())));
    EXPECT_EQ(m.schema_name, "foxglove.SceneUpdate");
    EXPECT_EQ(scene_times[m.log_time_ns], 1) << "a SceneUpdate at a time no SceneState has";
    ++updates;
    for (const auto& s : u.entities(1).spheres()) red += s.color().r() > 0.8 && s.color().g() < 0.3;
    return true;
  });
  EXPECT_GT(updates, 50);
  EXPECT_EQ(static_cast<std::size_t>(updates), scene_times.size());
  EXPECT_GT(red, 0);
  const RunResult reader = run("ENACT_NODE_MODULES=" + kModules + " node " + source_path("tests/interop/read_mcap.mjs") + " " + out);
  ASSERT_EQ(reader.exit_code, 0) << reader.err;
  EXPECT_NE(reader.out.find("\"foxglove/scene\":" + std::to_string(updates)), std::string::npos) << reader.out;
  // twice is refused
  EXPECT_EQ(run(std::string(ENACT_CLI) + " export " + out + " --foxglove " + dir.file("again.mcap")).exit_code, 1);
}

TEST(FoxgloveBridgeCli, RefusesABadPortAndHasHelp) {
  EXPECT_EQ(run(std::string(ENACT_CLI) + " foxglove --port 70000 --attach tcp://127.0.0.1:1").exit_code, 2);
  const RunResult help = run(std::string(ENACT_CLI) + " foxglove --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("foxglove.websocket.v1"), std::string::npos);
}

}  // namespace
}  // namespace enact::test
