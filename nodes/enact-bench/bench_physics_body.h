#pragma once
// enact bench physics, the deformable body's rows (bench_physics_body.cpp): the bridge explored
// by the deformable fingertip (launch/scenes/bridge_deformable.yaml) along its scripted hand
// path, through each integrator at each rate, against cordis at the reference rate.
#include <string>
#include <vector>

#include "nodes/enact/json.h"
#include "core/physics/reference.h"

namespace enact::cli {

struct BodyRows {
  std::string scene;
  std::vector<physics::reference::SweepRow> rows;
};

// the rows for `scene` (found from the current directory, else the source tree), CM1
BodyRows deformable_rows(const std::string& scene, double reference_hz);
void print_deformable_rows(const BodyRows& rows);
void deformable_rows_json(Json& j, const BodyRows& rows);

}  // namespace enact::cli
