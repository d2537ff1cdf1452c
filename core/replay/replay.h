#pragma once
// Offline replay of a recording through the simulator component, with no bus: the recorded
// device states (ffd/state) step a fresh simulator configured as the recorded one was (its
// parameters from the recording's metadata, its scene and computer-model files from the
// attachments), and its forces and tactile frames are compared with the recorded ffd/force
// and tactile/frame, bit for bit. The live parameter changes the simulator acknowledged
// (param/ack: the value applied and the state whose step first used it) are re-applied
// before that step. A regression check for the physics, and the way to recompute a trial's
// metrics from its recording alone.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/devices/device.h"
#include "core/graph/temp_folder.h"
#include "core/record/reader.h"
#include "core/sim/simulator.h"
#include "core/task/bridge_task.h"

namespace enact::graph {

// a stage of the recorded loop (a node::LoopComponent a user wrote: core/node/loop_component.h)
// as the recording names it (its enact.components metadata), with its parameters as recorded
struct RecordedStage {
  std::string name, plugin, library;
  std::map<std::string, std::string> params;  // scoped: "stiffness_n_per_m", not "rt.guide.stiffness_n_per_m"
};
// the recorded stages stepping on one tick, in order, as the loop stepped them after the
// model: the tick's time, the model's, the device sample as recorded (its faults not: 0), the
// model's output for them to change
using StageStep = std::function<void(std::int64_t time_ns, std::int64_t model_time_ns, const devices::ForceSample& sample, sim::StepOutput& step)>;

struct ResimOptions {
  std::string scene;  // scene file; "" = the recorded one
  std::string model;  // computer model (preset or file); "" = the recorded one
  // makes the recorded stages again (node::replay_stages loads their libraries); without it a
  // recording whose loop had stages is refused, naming them and the fix
  std::function<StageStep(const std::vector<RecordedStage>&)> stages;
};

// the first place the replay differs from the recording
struct Divergence {
  std::uint64_t step = 0;        // 0-based step of the replay
  std::uint64_t state_seq = 0;   // header.seq of the device state of that step
  std::string topic, field;      // e.g. "ffd/force", "force.x"
  std::string recorded, replayed;
};

// where a replay starts: the graph's first tick, or a keyframe (sim/keyframe) of the
// simulator when the recording starts later
struct ReplayStart {
  std::uint64_t first_state_seq = 0;  // of the recording's first device state (1: the graph's first tick)
  bool mid_run = false;               // the recording starts after the graph's first tick
  bool keyframe = false;              // ... and holds a keyframe to start from
  std::int64_t keyframe_stamp_ns = 0; // its device state's stamp (replay continues after it)
  std::uint64_t keyframe_state_seq = 0, keyframe_step = 0;
  double keyframe_time_s = 0.0;       // the simulator's time at it (since its first state)
  double skipped_s = 0.0;             // recorded before it (not replayed)
};

struct ResimResult {
  std::string scene, model;            // what the simulator ran (scene path as recorded)
  std::string clock = "real";          // the graph clock that made the recording (rt::GraphClock)
  double rate_hz = 0.0;
  std::uint64_t steps = 0;             // device states replayed
  std::uint64_t first_state_seq = 0;   // the first state replayed (1: the graph's first tick)
  ReplayStart start;
  std::uint64_t forces_compared = 0, frames_compared = 0;
  std::uint64_t forces_missing = 0;    // states the recording holds no answer to
  // of those, states the simulator never received (a stall filled the loop hop's queue, which
  // dropped them): the answers either side follow each other in the simulator's stream with
  // no gap, so it published nothing for them. Not stepped, as the simulator did not step them.
  std::uint64_t states_never_received = 0;
  std::uint64_t changes = 0;           // live parameter changes re-applied (param/ack)
  std::vector<RecordedStage> stages;   // the recorded loop's stages, stepped again after the model
  std::optional<Divergence> divergence;
  task::Metrics metrics;               // the bridge task's metrics of the replay
  bool task = true;                    // the scene has a task (else the metrics count nothing)
};

// where a replay of `r` starts (the first keyframe of the simulator that answered the states,
// after the recording's first state)
ReplayStart replay_start(record::Reader& r);
// where a replay starts, in words ("" from the graph's first tick)
std::string describe(const ReplayStart& start);

// the simulator's parameter `name` (scene, model, rate_hz, ...) as recorded in `recording` (the
// node or component that answered the device states); a file parameter (scene, model) as a
// copy of the recorded file in `files`, with the files it reads beside it. Throws
// config::Error naming the recording and the fix. For $(recorded ARG NAME) in launch files
std::string recorded_sim_param(const std::string& recording, const std::string& name, TempFolder& files);

// replays `r` from its start (replay_start; with another scene or model, from its first
// state); throws config::Error (naming the file and the fix) when the recording has no
// device states, or no scene is recorded and none is given
ResimResult resim(record::Reader& r, const ResimOptions& options);

}  // namespace enact::graph
