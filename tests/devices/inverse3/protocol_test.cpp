// The Inverse Service's messages (core/devices/inverse3/protocol.h), on messages shaped as
// Haply's documentation shows them (docs.haply.co: WebSocket Protocol, Control Commands,
// Events & Monitoring), written here by hand.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/devices/inverse3/protocol.h"

namespace enact::devices::inverse3 {
namespace {

TEST(Inverse3Protocol, AnInventoryGivesEachDeviceItsStateAndStatus) {
  const std::string text = R"({"session_id": 7,
    "inverse3": [{"device_id": "049D",
                  "config": {"type": "inverse3", "handedness": "right"},
                  "state": {"cursor_position": {"x": 0.01, "y": -0.12, "z": 0.15},
                            "cursor_velocity": {"x": 0.0, "y": 0.2, "z": -0.1}},
                  "status": {"calibrated": false, "in_use": true, "power_supply": true, "ready": true, "started": true}}],
    "verse_grip": [{"device_id": "61548", "state": {"button": true}}]})";
  Update u;
  std::string why;
  ASSERT_TRUE(parse_update(text, u, why)) << why;
  ASSERT_EQ(u.inverse3.size(), 1u);
  const DeviceEntry& d = u.inverse3[0];
  EXPECT_EQ(d.device_id, "049D");
  EXPECT_EQ(d.position_m.x, 0.01);
  EXPECT_EQ(d.position_m.y, -0.12);
  EXPECT_EQ(d.position_m.z, 0.15);
  EXPECT_EQ(d.velocity_m_per_s.y, 0.2);
  EXPECT_EQ(d.velocity_m_per_s.z, -0.1);
  EXPECT_TRUE(d.has_status);
  EXPECT_TRUE(d.in_use);
  EXPECT_TRUE(d.ready);
  EXPECT_EQ(u.buttons, 1u) << "the 3.4 grip's one button is bit 0";
}

TEST(Inverse3Protocol, TheNewerGripButtonsAreBitsAtoC) {
  Update u;
  std::string why;
  ASSERT_TRUE(parse_update(R"({"inverse3": [], "verse_grip": [{"state": {"buttons": {"a": false, "b": true, "c": true}}}]})", u, why));
  EXPECT_EQ(u.buttons, 0b110u);
}

TEST(Inverse3Protocol, WhatIsNotAnUpdateIsSaidSo) {
  Update u;
  std::string why;
  EXPECT_FALSE(parse_update("{not json", u, why));
  EXPECT_EQ(why, "not JSON");
  EXPECT_FALSE(parse_update(R"({"name": "device-connected"})", u, why));
  EXPECT_EQ(why, "no \"inverse3\" list");
}

TEST(Inverse3Protocol, AFieldOfTheWrongTypeIsRefusedNotThrown) {
  Update u;
  std::string why;
  EXPECT_FALSE(parse_update(R"({"inverse3": [{"device_id": 7}]})", u, why));
  EXPECT_NE(why.find("a field of the wrong type"), std::string::npos) << why;
  EXPECT_FALSE(parse_update(R"({"inverse3": [{"state": {"cursor_position": {"x": "far"}}}]})", u, why));
  EXPECT_FALSE(parse_update(R"({"inverse3": [3]})", u, why));
  EXPECT_TRUE(u.inverse3.empty()) << "nothing half-read is left";
  Event e;
  EXPECT_FALSE(parse_event(R"({"name": "device-busy", "data": {"device_id": [1]}})", e));
  EXPECT_NO_THROW(force_command(std::string("\xff\xfe"), {}));
}

TEST(Inverse3Protocol, TheForceCommandIsSetCursorForceForTheDevice) {
  const auto j = nlohmann::json::parse(force_command("049D", {0.5, -1.0, 1.5}, "enact"));
  const auto& d = j.at("inverse3").at(0);
  EXPECT_EQ(d.at("device_id"), "049D");
  const auto& v = d.at("commands").at("set_cursor_force").at("vector");
  EXPECT_EQ(v.at("x"), 0.5);
  EXPECT_EQ(v.at("y"), -1.0);
  EXPECT_EQ(v.at("z"), 1.5);
  EXPECT_EQ(j.at("session").at("configure").at("profile").at("name"), "enact");
  EXPECT_FALSE(nlohmann::json::parse(force_command("049D", {})).contains("session")) << "the profile goes on the first message only";
}

TEST(Inverse3Protocol, EventsThatStopTheDeviceAreKnown) {
  Event e;
  ASSERT_TRUE(parse_event(R"({"name": "device-safety-triggered", "category": "device", "level": "error",
                              "data": {"device_family": "inverse", "device_id": "049D", "safety_type": "ebrake_triggered"},
                              "message": "emergency brake"})", e));
  EXPECT_EQ(e.device_id, "049D");
  EXPECT_EQ(e.safety_type, "ebrake_triggered");
  EXPECT_TRUE(stops_device(e));
  e.safety_type = "fod_stage_changed";
  EXPECT_FALSE(stops_device(e)) << "a stage change is reported, not a stop";
  ASSERT_TRUE(parse_event(R"({"name": "device-disconnected", "level": "warning", "data": {"device_id": "049D"}})", e));
  EXPECT_TRUE(stops_device(e));
  EXPECT_FALSE(parse_event(R"({"level": "warning"})", e));
}

TEST(Inverse3Protocol, TheServiceFrameIsShiftedToEnactsOrigin) {
  const math::Vec3 origin{0.0, -0.14, 0.14};
  const math::Vec3 p = to_enact({0.01, -0.12, 0.15}, origin);
  EXPECT_NEAR(p.x, 0.01, 1e-15);
  EXPECT_NEAR(p.y, 0.02, 1e-15);
  EXPECT_NEAR(p.z, 0.01, 1e-15);
}

}  // namespace
}  // namespace enact::devices::inverse3
