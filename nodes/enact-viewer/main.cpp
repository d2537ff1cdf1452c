// enact-viewer: watch a running graph from this machine or another one, change its
// parameters, or take a snapshot (docs/viewer.md); its options: options.cpp
#include <cstdio>
#include <exception>

#include "core/config/yaml.h"
#include "nodes/enact-viewer/options.h"
#include "nodes/enact/args.h"

int main(int argc, char** argv) {
  std::optional<enact::viewer::ViewerOptions> o;
  try {
    o = enact::viewer::parse_options(argc, argv);
    if (!o) return 0;
  } catch (const enact::cli::UsageError& e) {
    std::fprintf(stderr, "enact-viewer: %s\n  (enact-viewer --help lists the options)\n", e.what());
    return 2;
  } catch (const enact::config::Error& e) {
    std::fprintf(stderr, "enact-viewer: error: %s\n", e.what());
    return 1;
  }
  try {
    return enact::viewer::run_viewer(*o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "enact-viewer: error: %s\n", e.what());
    return 1;
  }
}
