#pragma once
// Which running graph a tool attaches to (docs/concepts.md, "Graphs by name"): --graph NAME, --attach
// ENDPOINT, or the only graph running, and the keys for it (--key, --server-key); shared by
// enact topic, param, record, node and foxglove.
#include <initializer_list>
#include <optional>
#include <set>
#include <string>

#include "core/bus/client.h"
#include "core/session/registry.h"
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
    "                     $ENACT_KEY; docs/remote-access.md)\n"
    "  --server-key FILE.pub  the graph's public key (default: $ENACT_SERVER_KEY)\n";

// the options every attaching tool accepts (graph, attach, wait, key, server-key) and `own`
std::set<std::string> attach_options(std::initializer_list<std::string> own = {});

// a graph a tool attached to: its attach endpoint and the keys for it
struct Attached {
  std::string endpoint;
  std::string name;  // its name in the registry ("": an endpoint no running graph here has)
  bus::ClientKeys keys;
};

// the start every attaching command shares. --help: `help` and the attach options on stdout,
// returns 0; no positional argument while `verbs` (the command's verbs, e.g. "list |
// echo TOPIC") is not empty: the same on stderr, returns 2; `well_formed` false: UsageError
// "use: enact TOOL VERBS", or "unknown verb X (did you mean Y?)" when the first positional is
// none of `known_verbs`. Else it installs the stop handlers, attaches (attach_target,
// attach_keys) into `out` and returns nullopt: the command goes on.
std::optional<int> start_attached(const Args& a, const std::string& tool, const char* help, const std::string& verbs,
                                  const std::vector<std::string>& known_verbs, bool well_formed, Attached& out);

// the graph given by --graph / --attach / --wait (options the tool's parser must accept),
// waiting for it while no stop signal came (graph::install_stop_handlers first); prints
// "enact TOOL: attached to graph NAME at ENDPOINT" on stderr. Throws UsageError for
// several graphs and no name, or both options; config::Error when none appeared in time.
graph::GraphEntry attach_target(const Args& a, const std::string& tool);

// the keys of --key and --server-key (else $ENACT_KEY, $ENACT_SERVER_KEY; none: no keys);
// options the tool's parser must accept
bus::ClientKeys attach_keys(const Args& a);

}  // namespace enact::cli
