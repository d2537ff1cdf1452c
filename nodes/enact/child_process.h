#pragma once
// A child process of the command line (the replicates of `enact experiment`, the jobs of
// `enact sweep`): started with every signal unblocked (the parent blocks SIGINT / SIGTERM for
// its own loop) and its output appended to a log file.
#include <sys/types.h>

#include <string>
#include <vector>

namespace enact::cli {

// starts `argv` (argv[0] a path) with its stdout and stderr appended to `log` ("": this
// process's); with `die_with_parent` it gets SIGTERM when this process ends (a killed
// worker's job stops with it). Throws std::runtime_error when it cannot fork.
pid_t start_logged(const std::vector<std::string>& argv, const std::string& log, bool die_with_parent);

}  // namespace enact::cli
