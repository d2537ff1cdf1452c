#pragma once
// A 2-D polyline (the bridge centerline seen from above) and the projection of a point
// onto it: how far along the path the point is, and how far to the side.
#include <vector>

namespace enact::task {

struct Point2 {
  double x_m = 0.0;
  double y_m = 0.0;
};

struct Projection {
  double arc_length_m = 0.0;  // distance along the polyline to the closest point
  double fraction = 0.0;      // arc_length_m / length_m, in [0, 1]
  double lateral_m = 0.0;     // signed distance to the closest point (+ to the left of travel)
  int segment = 0;            // index of the closest segment
};

class Polyline {
 public:
  Polyline() = default;
  // throws std::invalid_argument when fewer than 2 points, a non-finite point or a
  // zero-length segment
  explicit Polyline(std::vector<Point2> points);

  // closest point on the polyline; a point equally close to two segments (inside a corner)
  // goes to the earlier one; a default-constructed polyline gives a zero projection;
  // allocates nothing
  Projection project(double x_m, double y_m) const;

  double length_m() const { return length_m_; }
  const std::vector<Point2>& points() const { return points_; }
  // the point at a given arc length (clamped to the ends), and the unit direction of travel
  // there (at a vertex, that of the segment starting there; past the end, the last segment's)
  Point2 at(double arc_length_m) const;
  Point2 direction_at(double arc_length_m) const;

 private:
  std::vector<Point2> points_;
  std::vector<double> cumulative_m_;  // arc length at each point
  double length_m_ = 0.0;
};

}  // namespace enact::task
