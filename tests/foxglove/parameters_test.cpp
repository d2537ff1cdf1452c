// What Foxglove clients send and ask, in enact's terms (core/foxglove/parameters.h): a
// parameter's value typed for the Parameters panel, a panel's value as a ParamUpdate, a
// client-published message in json or protobuf as its Protobuf message.
#include <gtest/gtest.h>

#include "core/foxglove/parameters.h"

namespace enact::foxglove {
namespace {

using nlohmann::json;

TEST(FoxgloveParameters, ValuesAreTypedAsTheParameterIs) {
  EXPECT_EQ(parameter("sim.stiffness_n_per_m", "6000", "number"), (json{{"name", "sim.stiffness_n_per_m"}, {"value", 6000.0}}));
  EXPECT_EQ(parameter("tactile.rows", "4", "integer")["value"], 4.0);
  EXPECT_EQ(parameter("rt.lock_memory", "true", "flag")["value"], true);
  EXPECT_EQ(parameter("sim.force", "false", "flag")["value"], false);
  EXPECT_EQ(parameter("sim.model", "CM1", "choice")["value"], "CM1");
  // text that looks like a number stays text; a number parameter that is not one stays text
  EXPECT_EQ(parameter("ffd.serial", "1234", "text")["value"], "1234");
  EXPECT_EQ(parameter("ffd.start_m", "0,0.1,0", "x,y,z")["value"], "0,0.1,0");
  EXPECT_EQ(parameter("x.rate_hz", "fast", "number")["value"], "fast");
  // none set: no value
  EXPECT_FALSE(parameter("ffd.subject", "", "text").contains("value"));
}

TEST(FoxgloveParameters, PanelValuesBecomeTheUpdateEnactParamSetSends) {
  msgs::ParamUpdate u;
  ASSERT_TRUE(set_value(u, json(2500)));
  EXPECT_EQ(u.value_case(), msgs::ParamUpdate::kNumber);
  EXPECT_EQ(u.number(), 2500.0);
  ASSERT_TRUE(set_value(u, json(true)));
  EXPECT_EQ(u.value_case(), msgs::ParamUpdate::kFlag);
  ASSERT_TRUE(set_value(u, json("CM3")));
  EXPECT_EQ(u.text(), "CM3");
  ASSERT_TRUE(set_value(u, json("0.5")));  // as the command line reads it: a number
  EXPECT_EQ(u.value_case(), msgs::ParamUpdate::kNumber);
  ASSERT_TRUE(set_value(u, json::array({0.01, 0, "2"})));
  EXPECT_EQ(u.text(), "0.01,0,2");
  EXPECT_FALSE(set_value(u, json(nullptr)));
  EXPECT_FALSE(set_value(u, json::object()));
}

TEST(FoxgloveParameters, PublishedMessagesDecodeFromJsonOrProtobuf) {
  msgs::ParamUpdate sent;
  sent.set_name("sim.threshold_m");
  sent.set_number(0.002);
  sent.set_request_id(18446744073709551615u);
  msgs::ParamUpdate got;
  EXPECT_EQ(decode("protobuf", sent.SerializeAsString(), got), "");
  EXPECT_EQ(got.SerializeAsString(), sent.SerializeAsString());
  // Protobuf's JSON mapping: camelCase or proto names, 64-bit integers as strings
  got.Clear();
  EXPECT_EQ(decode("json", R"({"name": "sim.threshold_m", "number": 0.002, "requestId": "18446744073709551615"})", got), "");
  EXPECT_EQ(got.SerializeAsString(), sent.SerializeAsString());
  got.Clear();
  EXPECT_EQ(decode("json", R"({"name": "sim.threshold_m", "number": 0.002, "request_id": "18446744073709551615"})", got), "");
  EXPECT_EQ(got.SerializeAsString(), sent.SerializeAsString());
  // the Publish panel's template lists every member of the oneof: the one filled in is set
  got.Clear();
  EXPECT_EQ(decode("json", R"({"header": {"seq": 0, "stamp_ns": 0, "source": ""}, "name": "sim.model", "number": 0, "text": "CM3", "flag": false, "request_id": 0})", got), "");
  EXPECT_EQ(got.value_case(), msgs::ParamUpdate::kText);
  EXPECT_EQ(got.text(), "CM3");
  got.Clear();
  EXPECT_EQ(decode("json", R"({"name": "sim.reset", "number": 0, "text": "", "flag": false})", got), "");
  EXPECT_EQ(got.value_case(), msgs::ParamUpdate::kNumber);
  EXPECT_NE(decode("json", R"({"name": "sim.model", "number": 2, "text": "CM3"})", got).find("oneof"), std::string::npos);
  // what does not fit the schema is refused with the reason
  EXPECT_NE(decode("json", R"({"nmae": "x"})", got).find("nmae"), std::string::npos);
  EXPECT_NE(decode("json", R"({"name": )", got), "");
  EXPECT_NE(decode("protobuf", std::string("\xff\xff\xff", 3), got), "");
  EXPECT_NE(decode("cdr", "", got).find("not one of json, protobuf"), std::string::npos);
}

}  // namespace
}  // namespace enact::foxglove
