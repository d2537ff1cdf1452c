#include "nodes/enact-viewer/options.h"

#include <cstdio>

#include "core/session/registry.h"
#include "nodes/enact/args.h"

namespace enact::viewer {
namespace {

constexpr const char* kHelp = R"(usage: enact-viewer [--graph NAME | --follow EXPERIMENT | --attach ENDPOINT] [--scene FILE] [--sim NAME]
                    [--key FILE.key --server-key FILE.pub]
                    [--snapshot OUT.png [--after SECONDS]] [--size WxH]
       enact-viewer FILE.mcap [--at SECONDS] [--scene FILE] [--snapshot OUT.png [--after SECONDS]]

Attach to a running graph and show it: the scene from above with the grid (masses in
contact highlighted) and its trail, the height against the top surface along the path,
the pins as shown, the forces, a scrolling plot of force and contacts, the task state and
every node's status. Change the computer model, threshold, stiffness and damping (checked
against the stability analysis before they are sent), reset, reposition, start and stop a
trial; each change is shown applied or refused with the simulator's reason. Keys: 0-3
CM0-CM3, r reset, p reposition, t trial start/stop, +/- stiffness x1.25, ]/[ threshold
+/-0.5 mm. The graph never notices a viewer coming or going.

With a recording (FILE.mcap, from `enact record` or enact-logger), play it instead, on a
timeline: play, pause, seek, speed (keys: space, ',' '.' 5 s back / on, '<' '>' speed).

options:
  --graph NAME       the running graph to watch (enact graph list), followed: a viewer
                     started first waits, and connects when the graph appears (again when
                     it is launched anew). Default: the only graph running (several: they
                     are listed, exit 2; none: it waits for one)
  --follow EXPERIMENT  an experiment's current trial (graphs EXPERIMENT/SUBJECT_CONDITION),
                     the next one as each trial ends
  --attach ENDPOINT  the graph's attach point (printed by `enact launch`; from another
                     machine: tcp://HOST:PORT of a graph launched with --allow-remote
                     and --access)
  --scene FILE       the scene to draw (default: the one the graph's launch names, or the
                     one attached to the recording)
  --sim NAME         the simulator's node or component name (default: as the graph names
                     it, else sim)
  --at SECONDS       recording: start there, paused (default: play from the start)
  --snapshot OUT.png render, write OUT.png, print what it shows, exit
  --after SECONDS    when to take the snapshot, from the start (default 2)
  --key FILE.key     your secret key, for a graph launched with --access (default $ENACT_KEY)
  --server-key FILE.pub  the graph's public key (default $ENACT_SERVER_KEY;
                     docs/remote-access.md)
  --size WxH         window size in pixels (default 1280x800)
  --fps N            frames drawn per second at most (default 60; the scene comes at 60 Hz;
                     with software OpenGL a lower rate saves processor time)
)";


}  // namespace

std::optional<ViewerOptions> parse_options(int argc, char** argv) {
  using cli::UsageError;
  ViewerOptions o;
  const cli::Args a = cli::parse(argc, argv, 1, {"graph", "follow", "attach", "scene", "sim", "snapshot", "after", "size", "at", "fps", "key", "server-key"}, {});
  if (a.flag("help")) {
    std::fputs(kHelp, stdout);
    return std::nullopt;
  }
  if (a.positional.size() > 1) throw UsageError("unexpected argument '" + a.positional[1] + "'");
  if (!a.positional.empty()) o.recording = a.positional[0];
  const int choices = a.has("graph") + a.has("follow") + a.has("attach");
  if (!o.recording.empty() && choices > 0) throw UsageError("give a recording or a graph to attach to, not both");
  if (choices > 1) throw UsageError("give one of --graph, --follow and --attach");
  if (o.recording.empty() && a.has("at")) throw UsageError("--at is for a recording");
  o.graph.graph = a.get("graph");
  o.graph.endpoint = a.get("attach");
  o.graph.prefix = a.has("follow") ? a.get("follow") + "/" : "";
  if (!o.recording.empty() && (a.has("key") || a.has("server-key"))) throw UsageError("--key and --server-key are for a live graph, not a recording");
  o.keys = bus::client_keys(a.get("key"), a.get("server-key"));
  // none named: several running graphs are not guessed between
  if (o.recording.empty() && choices == 0) {
    const auto running = graph::list_graphs();
    if (running.size() > 1) {
      std::string names;
      for (const auto& g : running) names += "\n  " + g.name + "  " + g.endpoint;
      throw UsageError("several graphs run; name one with --graph NAME:" + names);
    }
  }
  o.scene = a.get("scene");
  o.sim = a.get("sim");
  o.at_s = a.number("at", -1.0);
  if (a.has("at") && o.at_s < 0.0) throw UsageError("--at must be >= 0");
  o.fps = a.number("fps", o.fps);
  if (o.fps < 1.0 || o.fps > 240.0) throw UsageError("--fps must be from 1 to 240");
  o.snapshot = a.get("snapshot");
  o.after_s = a.number("after", o.after_s);
  if (o.after_s < 0.0) throw UsageError("--after must be >= 0");
  if (a.has("size") && (std::sscanf(a.get("size").c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 320 || o.height < 240)) {
    throw UsageError("--size needs WxH, at least 320x240");
  }
  return o;
}

}  // namespace enact::viewer
