#pragma once
// The subcommands of the `enact` command line; each returns the process exit code.
#include <string>

#include "core/bus/client.h"
#include "nodes/enact/args.h"

namespace enact::cli {

int check(int argc, char** argv);
int simulate(int argc, char** argv);
int path(int argc, char** argv);
int bench(int argc, char** argv);
int bench_loop(int argc, char** argv);
int bench_record(int argc, char** argv);
int launch(int argc, char** argv);
int topic(int argc, char** argv);
int record(int argc, char** argv);
int info(int argc, char** argv);
int export_csv(int argc, char** argv);
int recover(int argc, char** argv);
int play(int argc, char** argv);
int resim(int argc, char** argv);
int devices(int argc, char** argv);
int param(int argc, char** argv);
int keys(int argc, char** argv);

// --attach, else the endpoint of the last graph launched on this machine (UsageError if none)
std::string attach_endpoint(const Args& a);
// the keys of --key and --server-key (else $ENACT_KEY, $ENACT_SERVER_KEY; none: no keys)
bus::ClientKeys attach_keys(const Args& a);
// the help lines of --key and --server-key, shared by every attaching command
inline constexpr const char* kKeyHelp =
    "--key FILE.key, --server-key FILE.pub: for a graph launched with --access, your secret key\n"
    "and the graph's public key (default: $ENACT_KEY, $ENACT_SERVER_KEY; README, \"Remote access\").\n";
int experiment_run(int argc, char** argv);
int metrics(int argc, char** argv);

}  // namespace enact::cli
