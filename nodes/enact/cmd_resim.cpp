// enact resim FILE: the recorded device states through the simulator, offline; compared
// with the recorded forces and pins.
#include <cstdio>

#include "core/node/replay_stages.h"
#include "core/replay/replay.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/json.h"

namespace enact::cli {
namespace {

constexpr const char* kResimHelp = R"(usage: enact resim FILE [--scene S] [--model M] [--library PATH]... [--json]

Offline, with no bus: step a fresh simulator, configured as the recorded one (parameters
from the recording's metadata, scene and model files from its attachments), on every
recorded ffd/state, and compare its forces and tactile frames with the recorded ffd/force
and tactile/frame, bit for bit. A recording started on a running graph (its first ffd/state
is not the graph's first) replays from the simulator's first keyframe in it (sim/keyframe,
published once a second: the simulator's whole state), with the state after it. Live
parameter changes the simulator acknowledged (param/ack) are re-applied before the step that
first used them. The stages a user wrote for a co-located loop (plugin libraries, named in
the recording) step again after the model at every tick, from their recorded parameters.
With the recorded scene and model they must be identical
(a regression check for the physics); otherwise the first divergence is reported: the step,
the state's sequence number, the topic, the field and both values. Also prints the bridge
task's metrics of the replay.
Exit status: 0 identical, 1 diverged (or an error).

options:
  --scene S   run another scene file (from the recording's first state, no keyframe)
  --model M   run another computer model (preset or file; likewise)
  --library PATH
              a stage's plugin library, loaded first (the recorded one moved or was
              rebuilt); repeat for several
  --json      print the result as JSON
)";

}  // namespace

graph::ResimOptions replay_options(int& argc, char** argv) {
  std::vector<std::string> libraries;
  for (const std::string& l : take_repeated(argc, argv, "--library")) libraries.push_back(find_file(l));
  return {"", "", [libraries](const std::vector<graph::RecordedStage>& recorded) { return node::replay_stages(recorded, libraries); }};
}

int resim(int argc, char** argv) {
  graph::ResimOptions options = replay_options(argc, argv);
  const Args a = parse(argc, argv, 2, {"scene", "model"}, {"json"});
  if (a.flag("help")) {
    std::fputs(kResimHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one recording");
  record::Reader r(a.positional[0]);
  options.scene = a.has("scene") ? find_file(a.get("scene")) : "";
  options.model = a.get("model", "");
  const graph::ResimResult res = graph::resim(r, options);
  const task::Metrics& m = res.metrics;
  if (a.flag("json")) {
    Json j;
    j.begin_object();
    j.field("steps", static_cast<long long>(res.steps)).field("first_state_seq", static_cast<long long>(res.first_state_seq));
    j.field("from_keyframe", res.start.keyframe).field("keyframe_step", static_cast<long long>(res.start.keyframe_step));
    j.field("forces_compared", static_cast<long long>(res.forces_compared)).field("frames_compared", static_cast<long long>(res.frames_compared));
    j.field("forces_missing", static_cast<long long>(res.forces_missing)).field("changes", static_cast<long long>(res.changes));
    j.field("stages", static_cast<long long>(res.stages.size()));
    j.field("identical", !res.divergence);
    j.field("task", res.task);
    j.field("falls", m.falls).field("time_total_s", m.time_total_s).field("time_out_s", m.time_out_s).field("ratio", m.ratio);
    j.field("completed", m.completed);
    if (res.divergence) {
      const graph::Divergence& d = *res.divergence;
      j.key("divergence").begin_object();
      j.field("step", static_cast<long long>(d.step)).field("state_seq", static_cast<long long>(d.state_seq));
      j.field("topic", d.topic).field("field", d.field).field("recorded", d.recorded).field("replayed", d.replayed);
      j.end_object();
    }
    j.end_object();
    std::printf("%s\n", j.str().c_str());
    return res.divergence ? 1 : 0;
  }
  std::printf("resim %s: scene %s, model %s, %.0f Hz, %s time\n", r.path().c_str(), res.scene.c_str(), res.model.c_str(), res.rate_hz, res.clock.c_str());
  std::printf("  %llu device states replayed; %llu forces and %llu tactile frames compared\n", static_cast<unsigned long long>(res.steps),
              static_cast<unsigned long long>(res.forces_compared), static_cast<unsigned long long>(res.frames_compared));
  if (res.start.mid_run) std::printf("  the recording %s\n", graph::describe(res.start).c_str());
  for (const graph::RecordedStage& s : res.stages) {
    std::printf("  stage %s (plugin %s, %s) stepped after the model at every tick, as in the recorded loop\n", s.name.c_str(), s.plugin.c_str(), s.library.c_str());
  }
  if (res.changes) std::printf("  %llu live parameter changes re-applied where they took effect (param/ack)\n", static_cast<unsigned long long>(res.changes));
  if (res.forces_missing) {
    std::printf("  %llu states have no recorded answer", static_cast<unsigned long long>(res.forces_missing));
    if (res.states_never_received) {
      std::printf(" (%llu never reached the simulator: a stall filled the loop hop's queue; not stepped, as it did not)",
                  static_cast<unsigned long long>(res.states_never_received));
    }
    std::printf("\n");
  }
  if (res.task) {
    std::printf("  task: falls %d, time %.3f s, time out %.3f s, ratio %.4f, %s\n", m.falls, m.time_total_s, m.time_out_s, m.ratio,
                m.completed ? "completed" : "not completed");
  } else {
    std::printf("  no task in this scene: no falls or completion to count\n");
  }
  if (!res.divergence) {
    std::printf("  identical: every force and every pin frame is bit for bit the recorded one\n");
    return 0;
  }
  const graph::Divergence& d = *res.divergence;
  std::printf("  DIVERGED at step %llu (ffd/state seq %llu): %s %s: recorded %s, replayed %s\n", static_cast<unsigned long long>(d.step),
              static_cast<unsigned long long>(d.state_seq), d.topic.c_str(), d.field.c_str(), d.recorded.c_str(), d.replayed.c_str());
  return 1;
}

}  // namespace enact::cli
