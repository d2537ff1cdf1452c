#pragma once
// The viewer program (nodes/enact-viewer is its thin main): attach to a graph, draw it,
// send the experimenter's parameter changes; or take one snapshot and exit.
#include <string>

namespace enact::viewer {

struct ViewerOptions {
  std::string attach;     // the attach point's endpoint; "" follows the attach file
  std::string scene;      // the scene file the graph's simulator loaded
  std::string sim = "sim";  // the simulator's node or component name (its parameters' prefix)
  std::string snapshot;   // write this PNG after `after_s` and exit ("" : run until closed)
  double after_s = 2.0;   // seconds after the start
  int width = 1280;
  int height = 800;
};

// runs until the window is closed (or the snapshot is written); the exit code. Throws
// config::Error for a bad scene file, std::runtime_error when no window can be opened.
int run_viewer(const ViewerOptions& options);

}  // namespace enact::viewer
