// The one number parser: the whole text is the number, finite unless allowed, and every
// reader of numbers (trajectory CSV, node parameters) refuses what it refuses.
#include "core/config/number.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/config/yaml.h"
#include "core/task/trajectory.h"
#include "core/params/params.h"
#include "tests/support/test_util.h"

namespace enact::config {
namespace {

TEST(ParseNumber, TakesWholeDecimalNumbers) {
  EXPECT_EQ(parse_number("0.5"), 0.5);
  EXPECT_EQ(parse_number("-3e-3"), -3e-3);
  EXPECT_EQ(parse_number("6000"), 6000.0);
  EXPECT_EQ(parse_number("1E6"), 1e6);
}

TEST(ParseNumber, RefusesTextAroundOrInsteadOfANumber) {
  for (const char* bad : {"", " ", "0.5abc", "abc", " 1", "1 ", "1,5", "0x10", "--1", "1e", "e3"}) {
    EXPECT_FALSE(parse_number(bad)) << "'" << bad << "'";
  }
}

TEST(ParseNumber, NonFiniteOnlyWhenAllowed) {
  for (const char* text : {"nan", "inf", "-inf", "1e999"}) {
    EXPECT_FALSE(parse_number(text)) << text;
  }
  EXPECT_TRUE(std::isnan(*parse_number("nan", true)));
  EXPECT_EQ(*parse_number("-inf", true), -INFINITY);
}

TEST(ParseInteger, WholeTextWithinRange) {
  EXPECT_EQ(parse_integer("42"), 42);
  EXPECT_EQ(parse_integer("-7"), -7);
  for (const char* bad : {"", "4.0", "4x", " 4", "99999999999999999999"}) EXPECT_FALSE(parse_integer(bad)) << "'" << bad << "'";
}

TEST(ParseNumber, ATrajectoryCellWithTrailingTextIsRefusedNamingTheLine) {
  const test::TempDir dir;
  test::write_file(dir.file("path.csv"), "t_s,x_m,y_m,z_m\n0,0,0,0.013\n0.5abc,0,0,0.012\n");
  try {
    task::load_trajectory(dir.file("path.csv"));
    FAIL() << "0.5abc was read as a number";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("path.csv:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'0.5abc' is not a number"), std::string::npos) << e.what();
  }
}

TEST(ParseNumber, NodeParametersUseTheSameRule) {
  auto declared = [](const std::string& name, graph::ParamType type, const std::string& value) {
    graph::Params p("node");
    p.set(name, value);
    graph::ParamSpec spec;
    spec.name = name;
    spec.type = type;
    p.declare({spec});
    return p;
  };
  EXPECT_THROW(declared("k", graph::ParamType::number, "0.5abc"), Error);
  EXPECT_THROW(declared("start_m", graph::ParamType::vec3, "0,0,1x"), Error);
  EXPECT_EQ(declared("n", graph::ParamType::integer, "12").integer("n"), 12);
}

}  // namespace
}  // namespace enact::config
