// The recording view: a recording played into the viewer's model on a timeline (seek both
// ways, play at a speed, stop at the end), with the scene attached to it.
#include "core/viewer/playback.h"

#include <gtest/gtest.h>

#include "core/config/yaml.h"
#include "core/record/mcap.h"
#include "core/record/writer.h"
#include "msgs/node_status.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/task_event.pb.h"
#include "tests/support/test_util.h"

namespace enact::viewer {
namespace {

constexpr std::int64_t kStart_ns = 1'000'000'000'000;  // the recording's clock at its first message
constexpr std::int64_t kMs = 1'000'000;

// a recording as the logger writes one: a scene every 100 ms for 1 s (body x = k mm at
// k x 100 ms), a fall at 500 ms, a node status at 0, other traffic, the scene attached
std::string make_recording(const test::TempDir& dir, bool with_viewer_topics = true) {
  const std::string path = dir.file("trial.mcap");
  record::Writer w(path);
  const std::uint16_t schema = w.add_schema("enact.msgs.SceneState", "protobuf", "");
  const std::uint16_t scenes = w.add_channel(schema, "sim/scene", "protobuf", {{"publisher", "rt"}});
  const std::uint16_t events = w.add_channel(0, "task/event", "protobuf");
  const std::uint16_t status = w.add_channel(0, "node/status", "protobuf");
  const std::uint16_t states = w.add_channel(0, "ffd/state", "protobuf");
  w.write(states, 1, kStart_ns - 50 * kMs, 0, "not for the viewer");
  if (with_viewer_topics) {
    msgs::NodeStatus st;
    st.set_node("rt");
    st.set_rate_hz(5000);
    w.write(status, 1, kStart_ns, 0, st.SerializeAsString());
    for (int k = 0; k <= 10; ++k) {
      msgs::SceneState s;
      s.mutable_header()->set_stamp_ns(k * 100 * kMs);
      s.mutable_body_position()->set_x(k * 1e-3);
      s.set_model("CM2");
      w.write(scenes, static_cast<std::uint32_t>(k + 1), kStart_ns + k * 100 * kMs, 0, s.SerializeAsString());
    }
    msgs::TaskEvent fall;
    fall.set_kind(msgs::TaskEvent::FALL_START);
    w.write(events, 1, kStart_ns + 500 * kMs, 0, fall.SerializeAsString());
  }
  w.add_attachment("rt.sim.scene", "application/yaml", test::read_file(test::source_path("launch/scenes/bridge.yaml")), kStart_ns);
  w.close();
  return path;
}

TEST(Playback, ReadsTheSpanAndTheAttachedScene) {
  const test::TempDir dir;
  const Playback p(make_recording(dir));
  EXPECT_EQ(p.duration_ns(), 1000 * kMs);
  EXPECT_EQ(p.position_ns(), 0);
  ASSERT_TRUE(p.scene());
  EXPECT_EQ(p.scene()->sim, "sim");
  EXPECT_NE(p.scene()->data.find("bridge"), std::string::npos);
}

TEST(Playback, SeeksForwardAndBackward) {
  const test::TempDir dir;
  Playback p(make_recording(dir));
  ViewModel m;
  p.seek(350 * kMs, m);
  ASSERT_TRUE(m.has_scene());
  EXPECT_DOUBLE_EQ(m.scene().body_position().x(), 0.003);
  EXPECT_EQ(m.trail().size(), 4u);
  EXPECT_EQ(m.task().falls, 0);
  EXPECT_EQ(m.nodes().at("rt").received_ns, kStart_ns);
  p.seek(750 * kMs, m);
  EXPECT_DOUBLE_EQ(m.scene().body_position().x(), 0.007);
  EXPECT_EQ(m.task().falls, 1);
  EXPECT_EQ(m.trail().size(), 8u);
  // back before the fall: replayed from the start, so the fall and the later trail are gone
  p.seek(200 * kMs, m);
  EXPECT_DOUBLE_EQ(m.scene().body_position().x(), 0.002);
  EXPECT_EQ(m.task().falls, 0);
  EXPECT_EQ(m.trail().size(), 3u);
  // clamped to the recording
  p.seek(-5 * kMs, m);
  EXPECT_EQ(p.position_ns(), 0);
  p.seek(99'000 * kMs, m);
  EXPECT_EQ(p.position_ns(), p.duration_ns());
  EXPECT_DOUBLE_EQ(m.scene().body_position().x(), 0.010);
}

TEST(Playback, PlaysAtItsSpeedAndStopsAtTheEnd) {
  const test::TempDir dir;
  Playback p(make_recording(dir));
  ViewModel m;
  p.seek(0, m);
  p.advance(100 * kMs, m);
  EXPECT_EQ(p.position_ns(), 0);  // paused
  p.set_playing(true);
  p.set_speed(2.0);
  p.advance(100 * kMs, m);
  EXPECT_EQ(p.position_ns(), 200 * kMs);
  EXPECT_DOUBLE_EQ(m.scene().body_position().x(), 0.002);
  p.on_key('<', m);
  EXPECT_DOUBLE_EQ(p.speed(), 1.0);
  p.on_key('.', m);  // 5 s on: the end
  EXPECT_EQ(p.position_ns(), p.duration_ns());
  p.advance(100 * kMs, m);
  EXPECT_FALSE(p.playing());
  p.on_key(' ', m);
  EXPECT_TRUE(p.playing());
}

TEST(Playback, RefusesWhatItCannotShow) {
  const test::TempDir dir;
  test::write_file(dir.file("not.mcap"), "not an mcap file at all");
  EXPECT_THROW(Playback(dir.file("not.mcap")), record::Error);
  EXPECT_THROW(Playback(make_recording(dir, false)), config::Error);
}

}  // namespace
}  // namespace enact::viewer
