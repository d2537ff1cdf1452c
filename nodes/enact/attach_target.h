#pragma once
// Which running graph a tool attaches to (README, "Graphs by name"): --graph NAME, --attach
// ENDPOINT, or the only graph running, and the keys for it (--key, --server-key); shared by
// enact topic, param, record, node and foxglove.
#include <string>

#include "core/bus/client.h"
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
    "                     machine's graph launched with --allow-remote --access)\n"
    "  --wait S           give up when no such graph runs after S s (default: wait)\n"
    "  --key FILE.key     your secret key, for a graph launched with --access (default:\n"
    "                     $ENACT_KEY; README, \"Remote access\")\n"
    "  --server-key FILE.pub  the graph's public key (default: $ENACT_SERVER_KEY)\n";

// the graph given by --graph / --attach / --wait (options the tool's parser must accept),
// waiting for it while no stop signal came (graph::install_stop_handlers first); prints
// "enact TOOL: attached to graph NAME at ENDPOINT" on stderr. Throws UsageError for
// several graphs and no name, or both options; config::Error when none appeared in time.
graph::GraphEntry attach_target(const Args& a, const std::string& tool);

// the keys of --key and --server-key (else $ENACT_KEY, $ENACT_SERVER_KEY; none: no keys);
// options the tool's parser must accept
bus::ClientKeys attach_keys(const Args& a);

}  // namespace enact::cli
