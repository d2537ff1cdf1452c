#include "core/task/polyline.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace enact::task {
namespace {

std::string describe(const Point2& p) {
  return "(" + std::to_string(p.x_m) + ", " + std::to_string(p.y_m) + ")";
}

// index of the segment that holds an arc length: the one that starts at or before it, the
// first for arc lengths before the start and the last past the end
std::size_t segment_at(const std::vector<double>& cumulative_m, double arc_length_m) {
  const auto after = std::upper_bound(cumulative_m.begin(), cumulative_m.end(), arc_length_m);
  const auto starts = static_cast<std::size_t>(std::distance(cumulative_m.begin(), after));
  return std::clamp<std::size_t>(starts, 1, cumulative_m.size() - 1) - 1;
}

}  // namespace

Polyline::Polyline(std::vector<Point2> points) : points_(std::move(points)) {
  if (points_.size() < 2) {
    throw std::invalid_argument("Polyline needs at least 2 points, got " +
                                std::to_string(points_.size()));
  }
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (!std::isfinite(points_[i].x_m) || !std::isfinite(points_[i].y_m)) {
      throw std::invalid_argument("Polyline point " + std::to_string(i) + " is not finite " +
                                  describe(points_[i]));
    }
  }
  // arc length at each point; every segment must have a length
  cumulative_m_.reserve(points_.size());
  cumulative_m_.push_back(0.0);
  for (std::size_t i = 1; i < points_.size(); ++i) {
    const Point2& a = points_[i - 1];
    const Point2& b = points_[i];
    const double segment_m = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m);
    if (!(segment_m > 0.0)) {
      throw std::invalid_argument("Polyline segment " + std::to_string(i - 1) + " has zero length: points " +
                                  std::to_string(i - 1) + " and " + std::to_string(i) + " are both at " +
                                  describe(a) + "; remove the repeated point");
    }
    length_m_ += segment_m;
    cumulative_m_.push_back(length_m_);
  }
}

Projection Polyline::project(double x_m, double y_m) const {
  Projection best;
  double best_distance2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < points_.size(); ++i) {
    const Point2& a = points_[i - 1];
    const double dx = points_[i].x_m - a.x_m;
    const double dy = points_[i].y_m - a.y_m;
    const double segment_m = cumulative_m_[i] - cumulative_m_[i - 1];
    const double px = x_m - a.x_m;
    const double py = y_m - a.y_m;

    // closest point on this segment, as a fraction of it
    const double t = std::clamp((px * dx + py * dy) / (segment_m * segment_m), 0.0, 1.0);
    const double ex = px - t * dx;
    const double ey = py - t * dy;
    const double distance2 = ex * ex + ey * ey;
    // strictly closer only: on a tie (a corner) the earlier segment keeps the point
    if (distance2 < best_distance2) {
      best_distance2 = distance2;
      const double cross = dx * py - dy * px;  // > 0: left of the direction of travel
      best.segment = static_cast<int>(i - 1);
      best.arc_length_m = cumulative_m_[i - 1] + t * segment_m;
      best.lateral_m = std::copysign(std::sqrt(distance2), cross);
    }
  }
  if (length_m_ > 0.0) best.fraction = std::clamp(best.arc_length_m / length_m_, 0.0, 1.0);
  return best;
}

Point2 Polyline::at(double arc_length_m) const {
  if (points_.empty()) return {};
  const std::size_t i = segment_at(cumulative_m_, arc_length_m);
  const double segment_m = cumulative_m_[i + 1] - cumulative_m_[i];
  const double t = std::clamp((arc_length_m - cumulative_m_[i]) / segment_m, 0.0, 1.0);
  const Point2& a = points_[i];
  const Point2& b = points_[i + 1];
  return {a.x_m + t * (b.x_m - a.x_m), a.y_m + t * (b.y_m - a.y_m)};
}

Point2 Polyline::direction_at(double arc_length_m) const {
  if (points_.empty()) return {};
  const std::size_t i = segment_at(cumulative_m_, arc_length_m);
  const double segment_m = cumulative_m_[i + 1] - cumulative_m_[i];
  const Point2& a = points_[i];
  const Point2& b = points_[i + 1];
  return {(b.x_m - a.x_m) / segment_m, (b.y_m - a.y_m) / segment_m};
}

}  // namespace enact::task
