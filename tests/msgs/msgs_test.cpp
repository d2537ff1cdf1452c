#include <gtest/gtest.h>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <google/protobuf/stubs/logging.h>
#include <google/protobuf/util/message_differencer.h>

#include <cstdint>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "msgs/common.pb.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/graph.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"
#include "msgs/sim_keyframe.pb.h"
#include "msgs/task_state.pb.h"

namespace msgs = enact::msgs;
using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

namespace {

// messages that are values inside others, not sent on their own: the only ones without a header
const std::set<std::string> kValueTypes = {"enact.msgs.Vec3", "enact.msgs.Header"};

void fill(msgs::Header& h, std::uint64_t seq) {
  h.set_seq(seq);
  h.set_stamp_ns(1'234'567'890'123);
  h.set_source("simulator");
  h.set_sender_key("experimenter");
}

void fill(msgs::Vec3& v, double x, double y, double z) {
  v.set_x(x);
  v.set_y(y);
  v.set_z(z);
}

msgs::DeviceState device_state() {
  msgs::DeviceState m;
  fill(*m.mutable_header(), 42);
  fill(*m.mutable_position(), 0.012, -0.003, 0.0205);
  fill(*m.mutable_velocity(), 0.5, -1.25, 0.001);
  m.set_buttons(0b101);
  m.set_faults(msgs::DEVICE_FAULT_WATCHDOG | msgs::DEVICE_FAULT_OVER_FORCE);
  fill(*m.mutable_force(), -0.75, 0.25, 4.5);
  return m;
}

msgs::ForceCommand force_command() {
  msgs::ForceCommand m;
  fill(*m.mutable_header(), 43);
  m.set_answered_seq(42);
  fill(*m.mutable_force(), 1.5, -2.25, 12.0);
  m.set_zero(true);
  m.set_faults(msgs::COMMAND_FAULT_FORCE_CLAMPED);
  m.set_tactile_frame_seq(9);
  m.set_run_over(true);
  return m;
}

msgs::TactileFrame tactile_frame() {
  msgs::TactileFrame m;
  fill(*m.mutable_header(), 7);
  m.set_rows(4);
  m.set_cols(4);
  for (int i = 0; i < 16; ++i) m.add_level(i % 3 == 0 ? 1.0f : 0.25f);
  return m;
}

msgs::TactileShown tactile_shown() {
  msgs::TactileShown m;
  fill(*m.mutable_header(), 8);
  m.set_rows(4);
  m.set_cols(4);
  for (int i = 0; i < 16; ++i) m.add_level(static_cast<float>(i) / 15.0f);
  m.set_frame_seq(7);
  auto* motion = m.mutable_motion();
  motion->set_targets(0x00f0u);
  motion->set_stroke_ns(24e6);
  for (int i = 0; i < 16; ++i) {
    motion->add_from_level(static_cast<double>(i) / 15.0);
    motion->add_from_ns(1'000'000 + i);
  }
  return m;
}

msgs::SceneState scene_state() {
  msgs::SceneState m;
  fill(*m.mutable_header(), 9);
  fill(*m.mutable_body_position(), 0.01, 0.02, -0.001);
  for (int i = 0; i < 16; ++i) {
    fill(*m.add_contact_force(), 0.01 * (i + 1), -0.02, 0.1 * (i + 1));
    m.add_in_contact(i % 2 == 1);
    m.add_pin_level(i % 2 == 1 ? 1.0f : 0.0f);
  }
  fill(*m.mutable_resultant_force(), 0.5, -0.25, 12.0);
  m.set_model("CM2");
  m.set_on_top(true);
  m.set_progress(0.375);
  return m;
}

msgs::TaskEvent task_event() {
  msgs::TaskEvent m;
  fill(*m.mutable_header(), 3);
  m.set_kind(msgs::TaskEvent::FALL_START);
  m.set_time_ns(1'233'567'890'123);
  m.set_condition("CM3");
  m.set_subject("S07");
  m.set_trial(2);
  m.set_detail("left wall, second segment");
  return m;
}

msgs::TaskState task_state() {
  msgs::TaskState m;
  fill(*m.mutable_header(), 4);
  m.set_phase(msgs::TaskState::COMPLETED);
  m.set_trial_s(23.5);
  m.set_falls(2);
  m.set_time_out_s(3.25);
  m.set_progress(0.99);
  m.set_model("CM2");
  m.set_trial(3);
  m.set_falling(true);
  return m;
}

msgs::ParamUpdate param_update() {
  msgs::ParamUpdate m;
  fill(*m.mutable_header(), 1);
  m.set_name("simulator.stiffness_n_per_m");
  m.set_number(1500.0);
  m.set_request_id(77);
  return m;
}

msgs::ParamAck param_ack() {
  msgs::ParamAck m;
  fill(*m.mutable_header(), 2);
  m.set_request_id(77);
  m.set_applied(true);
  m.set_reason("clamped to 2000");
  m.set_name("sim.stiffness_n_per_m");
  m.set_number(2000.0);
  m.set_state_seq(5120);
  return m;
}

msgs::NodeStatus node_status() {
  msgs::NodeStatus m;
  fill(*m.mutable_header(), 60);
  m.set_node("simulator");
  m.set_state(msgs::NodeStatus::ACTIVE);
  m.set_rate_hz(4999.7);
  m.set_latency_p50_ns(21'000);
  m.set_latency_p99_ns(48'000);
  m.set_latency_p999_ns(95'000);
  m.set_latency_max_ns(180'000);
  m.set_jitter_p99_ns(12'000);
  m.set_overruns(3);
  auto* topic = m.add_topics();
  topic->set_topic("ffd/state");
  topic->set_sent(5);
  topic->set_received(300'000);
  topic->set_dropped(2);
  topic->set_malformed(1);
  m.set_faults(1);
  m.set_last_fault("model unstable: reset");
  m.set_watchdog_episodes(2);
  m.set_watchdog_longest_s(0.25);
  m.set_deadlines(50'000);
  m.set_deadlines_missed(12);
  m.set_verdict("this machine held 5000 Hz: 12 of 50000 deadlines missed (0.024 %), the force never cut");
  return m;
}

msgs::GraphInfo graph_info() {
  msgs::GraphInfo m;
  fill(*m.mutable_header(), 5);
  m.set_graph("bridge");
  auto* topic = m.add_topics();
  topic->set_name("ffd/state");
  topic->set_type("enact.msgs.DeviceState");
  topic->set_publisher("ffd");
  m.set_descriptor_set(std::string("\x0a\x00", 2));
  m.set_launch_file("launch/bridge.yaml");
  m.set_launch_text("launch: []\n");
  auto* param = m.add_params();
  param->set_name("sim.scene");
  param->set_value("scenes/bridge.yaml");
  auto* file = m.add_files();
  file->set_name("sim.scene");
  file->set_path("/x/scenes/bridge.yaml");
  file->set_media_type("application/yaml");
  file->set_data("rate_hz: 5000\n");
  m.set_loop_hop("local");
  m.set_clock("simulated");
  m.add_param_nodes("sim");
  m.add_param_nodes("ffd");
  auto* component = m.add_components();
  component->set_node("rt");
  component->set_name("guide");
  component->set_plugin("guide_spring");
  component->set_library("/x/libguide.so");
  return m;
}

// every field is set (non-empty when repeated, one member per oneof), recursively, so a
// round trip covers all of them and a field added later fails here until it is filled
void expect_all_fields_set(const Message& m) {
  const Descriptor* d = m.GetDescriptor();
  const auto* r = m.GetReflection();
  for (int i = 0; i < d->field_count(); ++i) {
    const FieldDescriptor* f = d->field(i);
    if (f->is_repeated()) {
      EXPECT_GT(r->FieldSize(m, f), 0) << f->full_name() << " is empty";
      if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
        for (int k = 0; k < r->FieldSize(m, f); ++k) expect_all_fields_set(r->GetRepeatedMessage(m, f, k));
      }
    } else if (f->real_containing_oneof() != nullptr) {
      EXPECT_TRUE(r->HasOneof(m, f->real_containing_oneof())) << f->full_name() << " oneof unset";
    } else {
      EXPECT_TRUE(r->HasField(m, f)) << f->full_name() << " has its default value";
      if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE && r->HasField(m, f)) {
        expect_all_fields_set(r->GetMessage(m, f));
      }
    }
  }
}

template <class T>
T round_trip(const T& sent) {
  std::string bytes;
  EXPECT_TRUE(sent.SerializeToString(&bytes));
  T received;
  EXPECT_TRUE(received.ParseFromString(bytes));
  return received;
}

template <class T>
void expect_round_trip(const T& sent) {
  expect_all_fields_set(sent);
  const T received = round_trip(sent);
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(sent, received))
      << "sent:\n" << sent.DebugString() << "received:\n" << received.DebugString();
}

// every stream message, one of each
std::vector<const Descriptor*> stream_messages() {
  return {msgs::DeviceState::descriptor(),  msgs::ForceCommand::descriptor(), msgs::TactileFrame::descriptor(),
          msgs::TactileShown::descriptor(), msgs::SceneState::descriptor(),   msgs::TaskEvent::descriptor(),
          msgs::ParamUpdate::descriptor(),  msgs::ParamAck::descriptor(),     msgs::NodeStatus::descriptor(),
          msgs::GraphInfo::descriptor(),    msgs::TaskState::descriptor(),    msgs::SimKeyframe::descriptor()};
}

// a header field as the contract wants it: `Header header = 1`, singular
::testing::AssertionResult has_header(const Descriptor* d) {
  const FieldDescriptor* f = d->FindFieldByName("header");
  if (f == nullptr) return ::testing::AssertionFailure() << d->full_name() << " has no field `header`";
  if (f->number() != 1 || f->is_repeated() || f->type() != FieldDescriptor::TYPE_MESSAGE ||
      f->message_type()->full_name() != "enact.msgs.Header") {
    return ::testing::AssertionFailure() << d->full_name() << ".header is not `enact.msgs.Header header = 1`";
  }
  return ::testing::AssertionSuccess();
}

}  // namespace

TEST(Msgs, DeviceStateRoundTrip) {
  expect_round_trip(device_state());
  const auto back = round_trip(device_state());
  EXPECT_EQ(back.header().seq(), 42u);
  EXPECT_EQ(back.position().z(), 0.0205);
}

TEST(Msgs, ForceCommandRoundTrip) {
  expect_round_trip(force_command());
  EXPECT_EQ(round_trip(force_command()).answered_seq(), 42u);
}

TEST(Msgs, TactileFrameRoundTrip) {
  expect_round_trip(tactile_frame());
  EXPECT_EQ(round_trip(tactile_frame()).level_size(), 16);
}

TEST(Msgs, TactileShownRoundTrip) { expect_round_trip(tactile_shown()); }

TEST(Msgs, SceneStateRoundTrip) {
  expect_round_trip(scene_state());
  const auto back = round_trip(scene_state());
  ASSERT_EQ(back.contact_force_size(), 16);
  EXPECT_EQ(back.contact_force(15).z(), 0.1 * 16);
  EXPECT_TRUE(back.in_contact(15));
}

TEST(Msgs, TaskEventRoundTrip) {
  expect_round_trip(task_event());
  EXPECT_EQ(round_trip(task_event()).kind(), msgs::TaskEvent::FALL_START);
}

msgs::SimKeyframe sim_keyframe() {
  msgs::SimKeyframe m;
  fill(*m.mutable_header(), 5);
  m.set_step(20001);
  m.set_origin_ns(1'000'000'000);
  m.set_model("CM1");
  fill(*m.mutable_body_position(), 0.01, -0.02, 0.011);
  m.set_trial_start_ns(1'000'000'000);
  m.set_falls(1);
  m.set_closed_out_ns(1'200'000'000);
  m.set_fall_since_ns(2'500'000'000);
  m.set_trial_end_ns(9'000'000'000);
  m.set_stopped(true);
  m.set_memory(std::string("\0\1keyframe", 10));
  return m;
}

TEST(Msgs, SimKeyframeRoundTrip) {
  expect_round_trip(sim_keyframe());
  EXPECT_EQ(round_trip(sim_keyframe()).memory(), std::string("\0\1keyframe", 10));
}

TEST(Msgs, TaskStateRoundTrip) {
  expect_round_trip(task_state());
  EXPECT_EQ(round_trip(task_state()).phase(), msgs::TaskState::COMPLETED);
}

TEST(Msgs, ParamUpdateRoundTripEachValueKind) {
  auto m = param_update();
  expect_round_trip(m);
  EXPECT_EQ(round_trip(m).value_case(), msgs::ParamUpdate::kNumber);
  m.set_text("CM1");
  expect_round_trip(m);
  EXPECT_EQ(round_trip(m).text(), "CM1");
  m.set_flag(true);
  expect_round_trip(m);
  EXPECT_EQ(round_trip(m).value_case(), msgs::ParamUpdate::kFlag);
}

TEST(Msgs, ParamAckRoundTrip) {
  auto m = param_ack();
  expect_round_trip(m);
  EXPECT_EQ(round_trip(m).state_seq(), 5120u);
  m.set_text("CM3");
  expect_round_trip(m);
  EXPECT_EQ(round_trip(m).value_case(), msgs::ParamAck::kText);
}

TEST(Msgs, GraphInfoRoundTrip) { expect_round_trip(graph_info()); }

TEST(Msgs, NodeStatusRoundTrip) {
  expect_round_trip(node_status());
  const auto back = round_trip(node_status());
  ASSERT_EQ(back.topics_size(), 1);
  EXPECT_EQ(back.topics(0).dropped(), 2u);
  EXPECT_EQ(back.state(), msgs::NodeStatus::ACTIVE);
}

TEST(Msgs, GarbageFailsToParse) {
  const std::string truncated = [] {
    std::string bytes = scene_state().SerializeAsString();
    bytes.resize(bytes.size() - 3);
    return bytes;
  }();
  const std::vector<std::string> garbage = {
      std::string("\x00\x01\x02", 3),         // field number 0
      std::string("\x0f\x01", 2),             // wire type 7 does not exist
      std::string("\x08\xff\xff\xff", 4),     // varint cut short
      std::string("\x0a\x7f\x01\x02", 4),     // length 127, 2 bytes follow
      truncated,                              // a real message cut short
  };
  for (const auto& bytes : garbage) {
    msgs::SceneState m;
    EXPECT_FALSE(m.ParseFromString(bytes)) << "parsed " << bytes.size() << " bytes of garbage";
  }
}

TEST(Msgs, InvalidUtf8InAStringFailsToParse) {
  // Header.source = "\xff\xfe": proto3 strings must be UTF-8
  const std::string bytes("\x1a\x02\xff\xfe", 4);
  const google::protobuf::LogSilencer quiet;  // protobuf logs the bad string
  msgs::Header h;
  EXPECT_FALSE(h.ParseFromString(bytes));
}

TEST(Msgs, HeaderWithTheWrongWireTypeLeavesNoHeader) {
  // field 1 sent as a varint: skipped as unknown, so the message fails the has_header() check
  const std::string bytes("\x08\x2a", 2);
  msgs::DeviceState m;
  ASSERT_TRUE(m.ParseFromString(bytes));
  EXPECT_FALSE(m.has_header());
}

TEST(Msgs, RandomBytesNeverCrashAndReparseStably) {
  std::mt19937 rng(12345);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> length(0, 64);
  const google::protobuf::LogSilencer quiet;  // protobuf logs bad strings
  for (int i = 0; i < 2000; ++i) {
    std::string bytes(static_cast<std::size_t>(length(rng)), '\0');
    for (char& c : bytes) c = static_cast<char>(byte(rng));
    msgs::NodeStatus m;
    if (!m.ParseFromString(bytes)) continue;
    // whatever parsed survives a second round trip unchanged
    const auto again = round_trip(m);
    EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(m, again));
  }
}

TEST(Msgs, EveryStreamMessageHasAHeader) {
  for (const Descriptor* d : stream_messages()) EXPECT_TRUE(has_header(d));
}

TEST(Msgs, EveryMessageInTheContractHasAHeaderExceptValueTypes) {
  // every .proto file in msgs/ must be linked here (include its .pb.h above and add its
  // messages to the tests), and every top-level message in it must have a header
  const std::filesystem::path dir = std::filesystem::path(ENACT_SOURCE_DIR) / "msgs";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".proto") continue;
    ++files;
    const std::string name = "msgs/" + entry.path().filename().string();
    const auto* file = google::protobuf::DescriptorPool::generated_pool()->FindFileByName(name);
    ASSERT_NE(file, nullptr) << name << " is not covered by msgs_test.cpp";
    EXPECT_EQ(file->package(), "enact.msgs") << name;
    EXPECT_EQ(file->syntax(), google::protobuf::FileDescriptor::SYNTAX_PROTO3) << name;
    for (int i = 0; i < file->message_type_count(); ++i) {
      const Descriptor* d = file->message_type(i);
      if (kValueTypes.count(d->full_name()) == 0) {
        EXPECT_TRUE(has_header(d)) << "in " << name;
      }
    }
  }
  EXPECT_GT(files, 0) << "no .proto file in " << dir;
}

TEST(Msgs, HeaderCheckRejectsAMessageWithoutHeader) {
  EXPECT_FALSE(has_header(msgs::Vec3::descriptor()));
  EXPECT_FALSE(has_header(msgs::NodeStatus::TopicCounters::descriptor()));
}
