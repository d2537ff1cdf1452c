// enact-bench: the benchmarks (`enact bench physics|loop|record` runs this with its arguments)
#include <cstdio>
#include <exception>
#include <string>

#include "core/config/yaml.h"
#include "nodes/enact/commands.h"

int main(int argc, char** argv) {
  try {
    if (argc < 2 || std::string(argv[1]) != "bench") throw enact::cli::UsageError("run it as: enact-bench bench physics|loop|record (or enact bench ...)");
    return enact::cli::bench(argc, argv);
  } catch (const enact::cli::UsageError& e) {
    std::fprintf(stderr, "enact bench: %s\n  (enact bench --help lists the options)\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "enact bench: error: %s\n", e.what());
    return 1;
  }
}
