#pragma once
// The rate sweep's rows (physics::reference::rate_sweep) as `enact check --rate-sweep` and
// `enact bench physics` print them: a table on stdout, or a JSON array.
#include <vector>

#include "core/physics/reference.h"
#include "nodes/enact/json.h"

namespace enact::cli {

// the rows as a table on stdout under a title
void print_sweep(const std::vector<physics::reference::SweepRow>& rows, const char* title);
// and as a JSON array
void sweep_json(Json& j, const std::vector<physics::reference::SweepRow>& rows);

}  // namespace enact::cli
