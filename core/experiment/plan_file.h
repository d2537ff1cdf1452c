#pragma once
// The keys bridge and discrimination experiment files share, read the same way (private to
// core/experiment): file:line errors with the fix.
#include <string>
#include <vector>

#include "core/config/yaml.h"
#include "core/experiment/experiment.h"

namespace enact::experiment {

// `subjects`: a count (ids 1..N) or a list of ids
std::vector<std::string> read_subjects(const config::Map& m);
// `conditions`: presets or computer-model files relative to the file
std::vector<Condition> read_conditions(const config::Map& m);
// `order`: random (default) or balanced
Order read_order(const config::Map& m);

}  // namespace enact::experiment
