#pragma once
// enact-viewer's command line: its options checked (cli::UsageError naming the problem), or
// nothing after printing --help
#include <optional>

#include "core/viewer/app.h"

namespace enact::viewer {

std::optional<ViewerOptions> parse_options(int argc, char** argv);

}  // namespace enact::viewer
