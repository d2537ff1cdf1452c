#pragma once
// The simulator component: one physical model stepped once per device sample, giving the
// force for the FFD and the pins for the tactile display from the same contacts, and the
// bridge task's state. Lifecycle: configure (load, validate, allocate) -> activate ->
// step ... -> deactivate. The same class runs in its own process or in a real-time
// container; step() allocates nothing, locks nothing and never throws.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/haptics/computer_model.h"
#include "core/haptics/tactile.h"
#include "core/physics/model.h"
#include "core/physics/stability.h"
#include "core/physics/state.h"
#include "core/sim/keyframe.h"
#include "core/sim/params.h"
#include "core/task/bridge_task.h"
#include "core/task/polyline.h"

namespace enact::sim {

struct StepOutput {
  math::Vec3 force_n;           // force for the device (N)
  int contacts = 0;                // grid masses touching
  std::uint32_t pins = 0;          // pin levels this step (bit i = pin i up)
  bool frame_due = false;          // a down-sampled tactile frame is due
  std::uint32_t frame = 0;         // that frame
  bool on_top = false;             // the body touches the task surface's top
  double progress = 0.0;           // position along the task path, [0, 1]
  task::TaskEvent event;           // a task event certain at this step
  bool fault = false;              // the divergence guard tripped this step (force is zero)
};

enum class Lifecycle : std::uint8_t { unconfigured, inactive, active };

class Simulator {
 public:
  // load and validate everything; throws config::Error (file:line and fix). An unstable
  // scene is refused unless params.force.
  void configure(const SimParams& params);
  void activate(std::int64_t start_ns = 0);
  void deactivate();
  // one step at time_ns on the model's clock, the body's proxy at device_position_m
  const StepOutput& step(std::int64_t time_ns, const math::Vec3& device_position_m);
  // one sample of the device at sample_ns on the device's clock, as every host runs the
  // simulator (enact-sim, the co-located loop, a replay): the first sample after activate()
  // is the model's time 0 (origin_ns); when the force path was cut (`cut`: the device's
  // watchdog or an error) and at the first sample, the body is first re-synchronised with the
  // device (Reengagement), so the force comes back from zero; a late sample (reengage.h) is
  // held at the depth of the one before. The task event's time is on the device's clock.
  // Allocates nothing, never throws.
  const StepOutput& step_sample(std::int64_t sample_ns, const math::Vec3& device_position_m, bool cut);

  // between steps: switch the computer model
  void set_computer_model(const haptics::ComputerModel& cm);
  // between steps: apply a change checked by a ParamPlanner (params.h); the next step is the
  // first to use it (a trial started or reset now begins at that step's time); `now_ns` is
  // copied into the result. A change of the force law (model, threshold, stiffness, damping,
  // reset, reposition) never jolts (docs/parameters.md, "Live changes never jolt"): each mass in contact
  // keeps the force it had and feels the new law only for what it moves from there, and the
  // rest blends away over change_ramp_s. Allocates nothing, never throws.
  ParamApplied apply(const ParamChange& change, std::int64_t now_ns);

  // everything it needs to continue from here (keyframe.h: the last sample, the origin and
  // the re-synchronisation too), into `out`: allocates nothing once `out` was filled before
  // by this simulator
  void save(Keyframe& out) const;
  // continue from a keyframe saved by a simulator configured alike (the same scene at the same
  // rate): the next step is the one after the keyframe's
  void restore(const Keyframe& keyframe);

  Lifecycle lifecycle() const { return lifecycle_; }
  const SimParams& params() const { return params_; }
  const physics::Model& model() const { return model_; }
  const physics::State& state() const { return state_; }
  const haptics::ComputerModel& computer_model() const { return cm_; }
  const physics::StabilityReport& stability() const { return stability_; }
  task::Metrics metrics() const { return task_.metrics(); }
  bool has_task() const { return !top_pairs_.empty(); }
  // a trial is running: the task counts falls and progress (from activate, or sim.trial start)
  bool trial_running() const { return trial_running_; }
  const task::Polyline& path() const { return path_; }
  int grid_masses() const;
  const StepOutput& output() const { return out_; }
  // steps since activate (ParamApplied::step counts the same way)
  std::uint64_t steps() const { return steps_; }
  // the device's clock at the model's time 0 (step_sample; -1 before the first sample)
  std::int64_t origin_ns() const { return origin_ns_; }
  const Reengagement& reengagement() const { return reengage_; }
  // the simulator's line of a host's summary: the task's falls and progress (a scene with a
  // task only), and the re-synchronisations with the device
  std::string summary() const;

 private:
  SimParams params_;
  Lifecycle lifecycle_ = Lifecycle::unconfigured;
  physics::Model model_;
  physics::State state_;
  physics::StabilityReport stability_;
  haptics::ComputerModel cm_;
  haptics::TactileDownsampler tactile_;
  task::BridgeTask task_;
  task::Polyline path_;
  template <class S, class K, class F>
  static void pair_fields(S& simulator, K& keyframe, F&& pair);
  // a change of the force law, before and after it is made (no jolt)
  void find_deepest();
  void keep_felt_forces();
  void reenter_contacts(bool from_scratch);
  void follow_reentry();
  math::Vec3 blend(const math::Vec3& model_force_n);

  std::vector<int> top_pairs_;  // contact pairs of the body with the task surface
  bool trial_running_ = true;
  // a trial a change started (or reset) begins at the next step; one it stopped ends with it
  TrialChange trial_change_ = TrialChange::none;
  std::uint64_t steps_ = 0;     // steps since activate
  Reengagement reengage_;
  std::int64_t origin_ns_ = -1, sample_ns_ = 0;  // step_sample's first and last sample
  std::int64_t late_steps_ns_ = 0;  // two of the model's steps: a sample later than this (and kLateSample_ns) is late
  // the live numbers changed since configure (bit n: row n of live_numbers()), their values
  std::array<double, kMaxLiveNumbers> live_values_{};
  std::uint32_t live_changed_ = 0;
  StepOutput out_;
  // no jolt: the body's points and contact pairs, each point's elastic force as the device
  // felt it before a change, whether some point counts its force from a re-entry depth, and
  // the force felt before the change, blending into the new law's (share: left / total steps)
  std::vector<int> body_points_, body_pairs_;
  std::vector<double> felt_n_;
  std::vector<double> felt_depth_m_;  // while re-entering: each point's depth beyond its re-entry depth
  std::vector<math::Vec3> felt_normal_;  // and the normal of the face it is felt through
  std::vector<int> deepest_pair_;  // each body point's deepest active contact pair (-1: none)
  bool reentering_ = false, capture_ = false;
  bool settling_ = false;  // the last step's force was held to the step limit on its way to the law's
  math::Vec3 from_n_;
  std::int64_t offset_left_ = 0, offset_total_ = 0;
  double max_step_n_ = 0.0;     // the device profile's force step limit per step (0: none)
  double reentry_step_m_ = 0.0; // how far a re-entry depth rises back per step
};

}  // namespace enact::sim
