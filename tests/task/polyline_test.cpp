#include "core/task/polyline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

using enact::task::Point2;
using enact::task::Polyline;

namespace {

constexpr double kTol = 1e-12;
const double kRoot2 = std::sqrt(2.0);

// the bridge seen from above: +45, -45, +45 degrees, right-angle turns at (1, 1) and (2, 0);
// each segment is sqrt(2) long
Polyline zigzag() { return Polyline({{0.0, 0.0}, {1.0, 1.0}, {2.0, 0.0}, {3.0, 1.0}}); }

}  // namespace

TEST(Polyline, LengthAndPoints) {
  const Polyline path = zigzag();
  EXPECT_NEAR(path.length_m(), 3.0 * kRoot2, kTol);
  EXPECT_EQ(path.points().size(), 4u);
}

TEST(Polyline, PointOnEachSegment) {
  const Polyline path = zigzag();
  const struct {
    double x, y;
    int segment;
    double arc;
  } cases[] = {
      {0.5, 0.5, 0, 0.5 * kRoot2},
      {1.5, 0.5, 1, 1.5 * kRoot2},
      {2.5, 0.5, 2, 2.5 * kRoot2},
  };
  for (const auto& c : cases) {
    const auto p = path.project(c.x, c.y);
    EXPECT_EQ(p.segment, c.segment) << c.x << ", " << c.y;
    EXPECT_NEAR(p.arc_length_m, c.arc, kTol);
    EXPECT_NEAR(p.fraction, c.arc / (3.0 * kRoot2), kTol);
    EXPECT_NEAR(p.lateral_m, 0.0, kTol);
  }
}

TEST(Polyline, LateralIsPositiveToTheLeftOfTravel) {
  const Polyline path = zigzag();
  const double h = 0.1;
  // segment 0 runs along (1, 1): its left is (-1, 1)
  auto p = path.project(0.5 - h, 0.5 + h);
  EXPECT_EQ(p.segment, 0);
  EXPECT_NEAR(p.lateral_m, h * kRoot2, kTol);
  EXPECT_NEAR(p.arc_length_m, 0.5 * kRoot2, kTol);
  p = path.project(0.5 + h, 0.5 - h);
  EXPECT_NEAR(p.lateral_m, -h * kRoot2, kTol);
  // segment 1 runs along (1, -1): its left is (1, 1)
  p = path.project(1.5 + h, 0.5 + h);
  EXPECT_EQ(p.segment, 1);
  EXPECT_NEAR(p.lateral_m, h * kRoot2, kTol);
  EXPECT_NEAR(p.arc_length_m, 1.5 * kRoot2, kTol);
  p = path.project(1.5 - h, 0.5 - h);
  EXPECT_NEAR(p.lateral_m, -h * kRoot2, kTol);
  // segment 2 is parallel to segment 0
  p = path.project(2.5 - h, 0.5 + h);
  EXPECT_EQ(p.segment, 2);
  EXPECT_NEAR(p.lateral_m, h * kRoot2, kTol);
}

TEST(Polyline, BeforeTheStartProjectsToTheStart) {
  const auto p = zigzag().project(-1.0, 0.0);
  EXPECT_EQ(p.segment, 0);
  EXPECT_EQ(p.arc_length_m, 0.0);
  EXPECT_EQ(p.fraction, 0.0);
  EXPECT_NEAR(p.lateral_m, 1.0, kTol);  // (-1, 0) is left of travel along (1, 1)
}

TEST(Polyline, PastTheEndProjectsToTheEnd) {
  const auto p = zigzag().project(4.0, 1.0);
  EXPECT_EQ(p.segment, 2);
  EXPECT_NEAR(p.arc_length_m, 3.0 * kRoot2, kTol);
  EXPECT_EQ(p.fraction, 1.0);
  EXPECT_NEAR(p.lateral_m, -1.0, kTol);  // (+1, 0) from the end is right of travel
}

TEST(Polyline, OutsideARightAngleCornerProjectsToTheVertex) {
  const Polyline path = zigzag();
  // the turn at (1, 1) is to the right: its outside is on the left
  auto p = path.project(1.0, 1.5);
  EXPECT_EQ(p.segment, 0);  // equally close to both: the earlier segment keeps it
  EXPECT_NEAR(p.arc_length_m, kRoot2, kTol);
  EXPECT_NEAR(p.fraction, 1.0 / 3.0, kTol);
  EXPECT_NEAR(p.lateral_m, 0.5, kTol);
  // the turn at (2, 0) is to the left: its outside is on the right
  p = path.project(2.0, -0.5);
  EXPECT_NEAR(p.arc_length_m, 2.0 * kRoot2, kTol);
  EXPECT_NEAR(p.lateral_m, -0.5, kTol);
  // the vertex itself
  p = path.project(1.0, 1.0);
  EXPECT_NEAR(p.arc_length_m, kRoot2, kTol);
  EXPECT_NEAR(p.lateral_m, 0.0, kTol);
}

TEST(Polyline, InsideARightAngleCornerProjectsToTheNearerSegment) {
  const Polyline path = zigzag();
  // inside the turn at (1, 1), nearer segment 0: closest point (0.85, 0.85)
  auto p = path.project(0.95, 0.75);
  EXPECT_EQ(p.segment, 0);
  EXPECT_NEAR(p.arc_length_m, 0.85 * kRoot2, kTol);
  EXPECT_NEAR(p.lateral_m, -0.1 * kRoot2, kTol);
  // mirrored, nearer segment 1: closest point (1.15, 0.85)
  p = path.project(1.05, 0.75);
  EXPECT_EQ(p.segment, 1);
  EXPECT_NEAR(p.arc_length_m, 1.15 * kRoot2, kTol);
  EXPECT_NEAR(p.lateral_m, -0.1 * kRoot2, kTol);
}

TEST(Polyline, AtAndDirectionAt) {
  const Polyline path = zigzag();
  const auto expect_point = [](Point2 actual, double x, double y) {
    EXPECT_NEAR(actual.x_m, x, kTol);
    EXPECT_NEAR(actual.y_m, y, kTol);
  };
  expect_point(path.at(0.0), 0.0, 0.0);
  expect_point(path.at(0.5 * kRoot2), 0.5, 0.5);
  expect_point(path.at(kRoot2), 1.0, 1.0);
  expect_point(path.at(1.5 * kRoot2), 1.5, 0.5);
  expect_point(path.at(-1.0), 0.0, 0.0);   // clamped to the start
  expect_point(path.at(100.0), 3.0, 1.0);  // clamped to the end

  const double u = 1.0 / kRoot2;
  expect_point(path.direction_at(0.5 * kRoot2), u, u);
  expect_point(path.direction_at(1.5 * kRoot2), u, -u);
  expect_point(path.direction_at(2.5 * kRoot2), u, u);
  expect_point(path.direction_at(2.0 * kRoot2 + 1e-9), u, u);  // just past the second turn
  expect_point(path.direction_at(-1.0), u, u);
  expect_point(path.direction_at(100.0), u, u);
}

TEST(Polyline, ProjectionOfAPointAtAnArcLengthGivesItBack) {
  const Polyline path = zigzag();
  for (double s = 0.0; s <= path.length_m(); s += 0.1) {
    const Point2 q = path.at(s);
    const auto p = path.project(q.x_m, q.y_m);
    EXPECT_NEAR(p.arc_length_m, s, 1e-9);
    EXPECT_NEAR(p.lateral_m, 0.0, 1e-9);
  }
}

TEST(Polyline, DefaultIsEmptyAndProjectsToZero) {
  const Polyline path;
  EXPECT_EQ(path.length_m(), 0.0);
  const auto p = path.project(1.0, 2.0);
  EXPECT_EQ(p.arc_length_m, 0.0);
  EXPECT_EQ(p.fraction, 0.0);
  EXPECT_EQ(p.lateral_m, 0.0);
}

TEST(Polyline, InvalidPolylinesThrow) {
  EXPECT_THROW(Polyline(std::vector<Point2>{}), std::invalid_argument);
  EXPECT_THROW(Polyline({{1.0, 2.0}}), std::invalid_argument);
  EXPECT_THROW(Polyline({{0.0, 0.0}, {1.0, 1.0}, {1.0, 1.0}, {2.0, 0.0}}), std::invalid_argument);
  EXPECT_THROW(Polyline({{0.0, 0.0}, {0.0, 0.0}}), std::invalid_argument);
  EXPECT_THROW(Polyline({{0.0, 0.0}, {std::nan(""), 1.0}}), std::invalid_argument);
  EXPECT_THROW(Polyline({{0.0, 0.0}, {std::numeric_limits<double>::infinity(), 1.0}}), std::invalid_argument);
}

TEST(Polyline, ErrorNamesTheBadSegment) {
  try {
    Polyline({{0.0, 0.0}, {1.0, 1.0}, {1.0, 1.0}});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("segment 1"), std::string::npos) << e.what();
  }
}
