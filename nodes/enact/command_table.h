#pragma once
// The command table of `enact`: its usage, the dispatch to each command, and the command and
// parameter reference generated from the code (`enact help --markdown`, docs/cli.md).
#include <string>

namespace enact::cli {

// the usage: every command with its form and what it does
std::string usage();
// docs/cli.md: the commands, then every node's and component's parameters
std::string reference_markdown();
// enact help [--markdown]
int help(int argc, char** argv);
// runs the command argv[1] (usage and exit 2 when none or unknown); its exit code
int run_command(int argc, char** argv);

}  // namespace enact::cli
