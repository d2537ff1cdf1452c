#pragma once
// A device path: positions over time, linearly interpolated between samples. Read from and
// written to CSV (t_s,x_m,y_m,z_m); drives the offline simulator and the scripted hand of
// simulated devices.
#include <iosfwd>
#include <string>
#include <vector>

#include "core/math/vec3.h"

namespace enact::task {

struct Trajectory {
  std::vector<double> t_s;
  std::vector<math::Vec3> position_m;
  math::Vec3 at(double t_s) const;  // clamped to the ends
  double start_s() const { return t_s.front(); }
  double end_s() const { return t_s.back(); }
};

// CSV with the header t_s,x_m,y_m,z_m, times strictly increasing; errors name file:line
Trajectory load_trajectory(const std::string& path);
void write_trajectory(const Trajectory& trajectory, std::ostream& out);

}  // namespace enact::task
