#pragma once
// The subcommands of the `enact` command line; each returns the process exit code.
#include <string>

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
int foxglove_bridge(int argc, char** argv);
int doctor(int argc, char** argv);
// enact export FILE --foxglove OUT.mcap (from export_csv)
int export_foxglove(const Args& a);

// --attach, else the endpoint of the last graph launched on this machine (UsageError if none)
std::string attach_endpoint(const Args& a);
int experiment_run(int argc, char** argv);
int metrics(int argc, char** argv);

}  // namespace enact::cli
