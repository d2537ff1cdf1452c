// enact metrics FILE: a trial's metrics recomputed from its recording alone.
#include <cmath>
#include <cstdio>

#include "core/config/format.h"
#include "core/experiment/results.h"
#include "core/replay/replay.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kMetricsHelp = R"(usage: enact metrics FILE.mcap [--library PATH]... [--json]

Recompute a trial's metrics (falls, time_total_s, time_out_s, ratio, completed) from its
recording alone: the recorded device states (ffd/state) replayed through a simulator
configured as the recorded one (scene and computer model from the recording's attachments
and metadata, as enact resim does), the bridge task's 1 s rule applied to the replay.
They are compared with the metrics the live simulator reported in the same recording (its
task events: what enact experiment writes to results.csv); they agree when the replay is
identical to the recording (live parameter changes are re-applied where they took effect; a
replay that diverges never agrees). A recording started on a running graph is replayed from
the simulator's first keyframe in it (sim/keyframe, as enact resim does): both sides then
take the trial up from that keyframe (its start, falls and time out so far) and compare the
whole trial to the recording's end; the output says which.
Exit status: 0 they agree, 1 they differ (or an error).

options:
  --library PATH   a stage's plugin library, as enact resim takes it
  --json           print them as JSON
)";

// the replay and the live report agree: the same counts, times within a microsecond
bool agree(const task::Metrics& a, const task::Metrics& b) {
  constexpr double kTolerance_s = 1e-6;
  return a.falls == b.falls && a.completed == b.completed && std::abs(a.time_total_s - b.time_total_s) <= kTolerance_s &&
         std::abs(a.time_out_s - b.time_out_s) <= kTolerance_s;
}

std::string json(const task::Metrics& m) {
  return "\"falls\": " + std::to_string(m.falls) + ", \"time_total_s\": " + config::number(m.time_total_s) + ", \"time_out_s\": " +
         config::number(m.time_out_s) + ", \"ratio\": " + config::number(m.ratio) + ", \"completed\": " + (m.completed ? "true" : "false");
}

void print(const char* what, const task::Metrics& m) {
  std::printf("  %-9s falls %d, time %.4f s, time out %.4f s, ratio %.4f, %s\n", what, m.falls, m.time_total_s, m.time_out_s, m.ratio,
              m.completed ? "completed" : "not completed");
}

}  // namespace

int metrics(int argc, char** argv) {
  const graph::ResimOptions options = replay_options(argc, argv);
  const Args a = parse(argc, argv, 2, {}, {"json"});
  if (a.flag("help")) {
    std::fputs(kMetricsHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one recording");
  const std::string path = a.positional[0];
  record::Reader reader(path);
  const graph::ResimResult replay = graph::resim(reader, options);
  const graph::ReplayStart& start = replay.start;
  const experiment::RecordedTrial live = experiment::read_trial(path, start.keyframe ? start.keyframe_stamp_ns : 0);
  // a replay that diverges from the recording does not reproduce the live run, whatever its counts
  const bool same = !replay.divergence && agree(replay.metrics, live.metrics);
  if (a.flag("json")) {
    std::printf("{%s, \"progress\": %s, \"steps\": %llu, \"first_state_seq\": %llu, \"from_keyframe\": %s, \"state_gaps\": %llu, \"identical\": %s, \"live\": {%s}, \"agree\": %s}\n",
                json(replay.metrics).c_str(), config::number(replay.metrics.progress).c_str(), static_cast<unsigned long long>(replay.steps),
                static_cast<unsigned long long>(replay.first_state_seq), start.keyframe ? "true" : "false", static_cast<unsigned long long>(live.state_gaps),
                replay.divergence ? "false" : "true", json(live.metrics).c_str(), same ? "true" : "false");
    return same ? 0 : 1;
  }
  std::printf("metrics %s: scene %s, model %s, %.0f Hz, %llu device states\n", path.c_str(), replay.scene.c_str(), replay.model.c_str(),
              replay.rate_hz, static_cast<unsigned long long>(replay.steps));
  // what is compared
  if (!start.mid_run) std::printf("  compared: the trial from the graph's first tick to the recording's end\n");
  else std::printf("  the recording %s\n", graph::describe(start).c_str());
  if (start.keyframe) {
    std::printf("  compared: the whole trial to the recording's end, taken up at the keyframe (its start, falls and time out so far),\n"
                "  the replay stepping every state after it, the live side adding the simulator's task events after it\n");
  }
  print("replayed", replay.metrics);
  print("live", live.metrics);
  if (live.state_gaps) std::printf("  note: the recording misses device states: the replay cannot match the live run exactly\n");
  if (replay.divergence) {
    std::printf("  the replay diverges from the recording at step %llu (ffd/state seq %llu, %s %s): enact resim %s says more\n",
                static_cast<unsigned long long>(replay.divergence->step), static_cast<unsigned long long>(replay.divergence->state_seq),
                replay.divergence->topic.c_str(), replay.divergence->field.c_str(), path.c_str());
  }
  std::printf("  %s\n", same ? "agree: the replay gives the metrics the live simulator reported" : "DIFFER: see above");
  return same ? 0 : 1;
}

}  // namespace enact::cli
