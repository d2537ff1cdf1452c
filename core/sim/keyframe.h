#pragma once
// A keyframe: everything a simulator needs to continue bit for bit from the step it follows
// (the body and every contact's memory, friction anchors included, the task, the pins'
// down-sampling, the live parameters in force, the no-jolt blend of a change settling, the
// body's re-synchronisation with the device). The simulator publishes one at a low rate
// (topic sim/keyframe), so `enact resim` and `enact metrics` start at the first keyframe of a
// recording made on a running graph (docs/recording-and-replay.md).
//
// Simulator::save fills one without allocating once it is sized (a first save sizes it), so
// a real-time thread takes it; pack/unpack turn it into bytes and back off that thread.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/haptics/tactile.h"
#include "core/physics/state.h"
#include "core/sim/params.h"
#include "core/sim/reengage.h"
#include "core/task/bridge_task.h"

namespace enact::sim {

// a trial a live change started (or reset) begins at the next step; one it stopped ends with it
enum class TrialChange : std::uint8_t { none, start, stop };

struct Keyframe {
  // the step it follows: the simulator's count, the device sample's stamp (its ffd/state's
  // header.stamp_ns), and the device clock's time of the simulator's time 0
  std::uint64_t step = 0;
  std::int64_t sample_ns = 0;
  std::int64_t origin_ns = 0;
  // live parameters in force: computer model, per contact pair and per point
  ModelChange model;
  double change_ramp_s = 0.0;
  std::vector<double> stiffness_n_per_m, damping_n_s_per_m;
  std::vector<double> threshold_m;
  std::vector<std::uint8_t> feeds_device;
  physics::State state;
  task::BridgeTask task;
  bool trial_running = true;
  TrialChange trial_change = TrialChange::none;
  haptics::TactileDownsampler tactile;
  // the no-jolt blend of a change (Simulator's)
  math::Vec3 force_n, from_n;
  bool reentering = false, capture = false, settling = false;
  std::int64_t offset_left = 0, offset_total = 0;
  double reentry_step_m = 0.0;
  std::vector<double> felt_depth_m;
  std::vector<math::Vec3> felt_normal;
  Reengagement reengage;
  // live numbers changed since the simulator was configured (bit n: live_numbers()[n]) and their values
  std::array<double, kMaxLiveNumbers> live_values{};
  std::uint32_t live_changed = 0;
};

// the bytes of a keyframe (its format names this build's layout); `out` is reused
void pack(const Keyframe& keyframe, std::string& out);
// back from bytes into a keyframe sized for the same scene (a save from the simulator that
// will restore it); false when the bytes are not a keyframe of this scene and build
bool unpack(const std::string& bytes, Keyframe& keyframe);

}  // namespace enact::sim
