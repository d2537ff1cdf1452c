#include "core/task/trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <ostream>
#include <sstream>

#include "core/config/format.h"
#include "core/config/number.h"
#include "core/config/share.h"
#include "core/config/yaml.h"

namespace enact::task {
namespace {

using config::number;

[[noreturn]] void bad_row(const std::string& path, int line, const std::string& problem) {
  throw config::Error(path + ":" + std::to_string(line) + ": " + problem +
                      "\n  fix: each row is t_s,x_m,y_m,z_m: four finite numbers, times increasing");
}

}  // namespace

math::Vec3 Trajectory::at(double t) const {
  if (t <= t_s.front()) return position_m.front();
  if (t >= t_s.back()) return position_m.back();
  const auto it = std::upper_bound(t_s.begin(), t_s.end(), t);
  const std::size_t i = static_cast<std::size_t>(it - t_s.begin());
  const double a = (t - t_s[i - 1]) / (t_s[i] - t_s[i - 1]);
  return position_m[i - 1] + (position_m[i] - position_m[i - 1]) * a;
}

Trajectory load_trajectory(const std::string& given) {
  const std::string path = config::find_file(given);
  std::ifstream in(path);
  if (!in) throw config::Error(path + ": cannot open the trajectory\n  fix: check the path");
  Trajectory tr;
  std::string row;
  int line = 0;
  if (!std::getline(in, row) || (++line, row.rfind("t_s,x_m,y_m,z_m", 0) != 0)) {
    throw config::Error(path + ":1: the first line must be the header t_s,x_m,y_m,z_m\n  fix: add that header line");
  }
  while (std::getline(in, row)) {
    ++line;
    if (row.empty() || row == "\r") continue;
    double v[4];
    std::stringstream ss(row);
    std::string cell;
    for (int i = 0; i < 4; ++i) {
      if (!std::getline(ss, cell, ',')) bad_row(path, line, "expected 4 columns");
      const auto number = config::parse_number(cell, true);
      if (!number) bad_row(path, line, "'" + cell + "' is not a number");
      if (!std::isfinite(*number)) bad_row(path, line, "'" + cell + "' is not finite (NaN or Inf)");
      v[i] = *number;
    }
    if (!tr.t_s.empty() && v[0] <= tr.t_s.back()) bad_row(path, line, "time " + row.substr(0, row.find(',')) + " does not increase");
    tr.t_s.push_back(v[0]);
    tr.position_m.push_back({v[1], v[2], v[3]});
  }
  if (tr.t_s.size() < 2) throw config::Error(path + ": a trajectory needs at least 2 rows\n  fix: add rows t_s,x_m,y_m,z_m");
  return tr;
}

void write_trajectory(const Trajectory& tr, std::ostream& out) {
  out << "t_s,x_m,y_m,z_m\n";
  for (std::size_t i = 0; i < tr.t_s.size(); ++i) {
    const auto& p = tr.position_m[i];
    out << number(tr.t_s[i]) << ',' << number(p.x) << ',' << number(p.y) << ',' << number(p.z) << '\n';
  }
}

}  // namespace enact::task
