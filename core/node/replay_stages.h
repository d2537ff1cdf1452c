#pragma once
// The stages a user wrote for a recorded co-located loop, made again for its replay (enact
// resim, enact metrics): graph::resim steps them after the model at every recorded tick.
#include <string>
#include <vector>

#include "core/replay/replay.h"

namespace enact::node {

// the stages of a recorded loop made again from their recorded parameters and activated,
// stepping as the loop stepped them: their plugins from `libraries` (loaded first: a library
// moved or rebuilt), else from the libraries recorded. Throws config::Error naming a library
// that is not there, or a stage it does not hold, and the fix
graph::StageStep replay_stages(const std::vector<graph::RecordedStage>& recorded, const std::vector<std::string>& libraries);

}  // namespace enact::node
