// enact resim FILE: the recorded device states through the simulator, offline; compared
// with the recorded forces and pins.
#include <cstdio>

#include "core/config/format.h"
#include "core/graph/replay.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact resim FILE [--scene S] [--model M] [--json]

Offline, with no bus: step a fresh simulator, configured as the recorded one (parameters
from the recording's metadata, scene and model files from its attachments), on every
recorded ffd/state, and compare its forces and tactile frames with the recorded ffd/force
and tactile/frame, bit for bit. With the recorded scene and model they must be identical
(a regression check for the physics); otherwise the first divergence is reported: the step,
the state's sequence number, the topic, the field and both values. Also prints the bridge
task's metrics of the replay.
Exit status: 0 identical, 1 diverged (or an error).

options:
  --scene S   run another scene file
  --model M   run another computer model (preset or file)
  --json      print the result as JSON
)";

}  // namespace

int resim(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"scene", "model"}, {"json"});
  if (a.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one recording");
  record::Reader r(a.positional[0]);
  const graph::ResimResult res = graph::resim(r, {a.has("scene") ? find_file(a.get("scene")) : "", a.get("model", "")});
  const task::Metrics& m = res.metrics;
  if (a.flag("json")) {
    std::printf("{\"steps\": %llu, \"first_state_seq\": %llu, \"forces_compared\": %llu, \"frames_compared\": %llu, \"forces_missing\": %llu, "
                "\"identical\": %s, \"falls\": %d, \"time_total_s\": %s, \"time_out_s\": %s, \"ratio\": %s, \"completed\": %s",
                static_cast<unsigned long long>(res.steps), static_cast<unsigned long long>(res.first_state_seq),
                static_cast<unsigned long long>(res.forces_compared), static_cast<unsigned long long>(res.frames_compared),
                static_cast<unsigned long long>(res.forces_missing), res.divergence ? "false" : "true", m.falls,
                config::number(m.time_total_s).c_str(), config::number(m.time_out_s).c_str(), config::number(m.ratio).c_str(),
                m.completed ? "true" : "false");
    if (res.divergence) {
      const graph::Divergence& d = *res.divergence;
      std::printf(", \"divergence\": {\"step\": %llu, \"state_seq\": %llu, \"topic\": \"%s\", \"field\": \"%s\", \"recorded\": \"%s\", \"replayed\": \"%s\"}",
                  static_cast<unsigned long long>(d.step), static_cast<unsigned long long>(d.state_seq), d.topic.c_str(), d.field.c_str(),
                  d.recorded.c_str(), d.replayed.c_str());
    }
    std::printf("}\n");
    return res.divergence ? 1 : 0;
  }
  std::printf("resim %s: scene %s, model %s, %.0f Hz\n", r.path().c_str(), res.scene.c_str(), res.model.c_str(), res.rate_hz);
  std::printf("  %llu device states replayed; %llu forces and %llu tactile frames compared\n", static_cast<unsigned long long>(res.steps),
              static_cast<unsigned long long>(res.forces_compared), static_cast<unsigned long long>(res.frames_compared));
  if (res.first_state_seq > 1) {
    std::printf("  note: the recording starts at ffd/state seq %llu, not at the graph's first tick: the simulator's history before it is\n"
                "  unknown, so the replay may differ (record from the start: README, \"Recording and replay\")\n",
                static_cast<unsigned long long>(res.first_state_seq));
  }
  if (res.forces_missing) std::printf("  %llu states have no recorded answer\n", static_cast<unsigned long long>(res.forces_missing));
  std::printf("  task: falls %d, time %.3f s, time out %.3f s, ratio %.4f, %s\n", m.falls, m.time_total_s, m.time_out_s, m.ratio,
              m.completed ? "completed" : "not completed");
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
