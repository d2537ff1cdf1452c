#pragma once
// The viewer program (nodes/enact-viewer is its thin main): attach to a graph, draw it,
// send the experimenter's parameter changes; or play a recording on a timeline; or take
// one snapshot of either and exit.
#include <string>

#include "core/bus/client.h"
#include "core/session/registry.h"

namespace enact::viewer {

struct ViewerOptions {
  graph::AttachChoice graph;  // which graph to attach to (an endpoint, a name, a trial prefix; none: the only one)
  bus::ClientKeys keys;       // for a graph launched with an access file (none: plain)
  std::string recording;    // an MCAP recording to play instead of attaching ("" : live)
  std::string scene;        // the scene file; "" : the one the graph (or recording) names
  std::string sim;          // the simulator's name; "" : the one the graph names, else "sim"
  std::string snapshot;     // write this PNG after `after_s` and exit ("" : run until closed)
  double after_s = 2.0;     // seconds after the start
  double at_s = -1.0;       // recording: start paused at this time (s from its start); < 0: play from the start
  int width = 1280;
  int height = 800;
  double fps = 60.0;        // frames drawn per second at most
};

// runs until the window is closed (or the snapshot is written); the exit code. Throws
// config::Error for a bad scene file or recording, std::runtime_error when no window can
// be opened.
int run_viewer(const ViewerOptions& options);

}  // namespace enact::viewer
