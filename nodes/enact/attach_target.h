#pragma once
// Which running graph a tool attaches to (README, "Graphs by name"): --graph NAME, --attach
// ENDPOINT, or the only graph running; shared by enact topic, param, record and the viewer.
#include <string>

#include "core/graph/registry.h"
#include "nodes/enact/args.h"

namespace enact::cli {

// the options' lines for a --help text
inline constexpr const char* kAttachOptionsHelp =
    "  --graph NAME       the running graph to attach to (enact graph list); without it (and\n"
    "                     without --attach): the only graph running; when several run, they\n"
    "                     are listed and nothing is guessed (exit 2); when none runs, it\n"
    "                     waits for one\n"
    "  --attach ENDPOINT  an attach endpoint instead (printed by `enact launch`; another\n"
    "                     machine's graph launched with --allow-remote)\n"
    "  --wait S           give up when no such graph runs after S s (default: wait)\n";

// the graph given by --graph / --attach / --wait (options the tool's parser must accept),
// waiting for it while no stop signal came (graph::install_stop_handlers first); prints
// "enact TOOL: attached to graph NAME at ENDPOINT" on stderr. Throws UsageError for
// several graphs and no name, or both options; config::Error when none appeared in time.
graph::GraphEntry attach_target(const Args& a, const std::string& tool);

}  // namespace enact::cli
