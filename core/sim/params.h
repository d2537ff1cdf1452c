#pragma once
// Parameter changes of a running simulator (topic param/set, docs/parameters.md): a
// ParamPlanner checks each request off the loop, against a mirror of the simulator's model
// (stiffness and damping against the stability analysis), and turns an accepted one into a
// trivially copyable ParamChange; Simulator::apply then applies it between two steps without
// allocating. Both nodes use these two functions: enact-sim applies between DeviceStates,
// enact-rt hands the change to its real-time thread through an SPSC queue.
//
// Names (after the simulator's node or component name, e.g. "sim.stiffness_n_per_m"):
//   model               text: a computer model preset (CM0..CM3, P, T, PT) or a YAML file
//   threshold_m         number >= 0: penetration before force is felt (the current model's)
//   stiffness_n_per_m   number >= 0: every contact pair of the exploratory body
//   damping_n_s_per_m   number >= 0: every contact pair of the exploratory body
//   change_ramp_s       number 0..10: the blend time of the next changes (SimParams)
//   reset               command: model, pins and task back to their start (a new trial)
//   reposition          command: the subject is put back at the start; contact memory is
//                       cleared, the trial goes on
//   trial               "start" (or true): a new trial from now; "stop" (or false): the
//                       trial ends, its metrics are kept
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/haptics/computer_model.h"
#include "core/physics/model.h"

namespace enact::sim {

class Simulator;

// the most changes planned but not applied yet at any time (the capacity of a loop's queues)
inline constexpr std::size_t kMaxParamsInFlight = 16;

// the value of a request as sent on the bus: at most one of them is set
struct ParamValue {
  std::optional<double> number;
  std::optional<std::string> text;
  std::optional<bool> flag;
};

enum class ParamKind : std::uint8_t { model, threshold, stiffness, damping, reset, reposition, trial_start, trial_stop, change_ramp };

// the longest computer model name a change carries (the loop cannot allocate a longer one)
inline constexpr std::size_t kMaxModelName = 63;

// a computer model without its allocating parts, for the loop
struct ModelChange {
  std::uint32_t force_grid_mask = 0;
  bool force_center = false;
  std::uint32_t pin_mask = 0;
  haptics::PinDrive pins = haptics::PinDrive::none;
  double threshold_m = 0.0;
  char name[kMaxModelName + 1] = {};
};

// a checked change, ready for the loop (trivially copyable: it goes through an SPSC queue)
struct ParamChange {
  std::uint64_t request_id = 0;
  ParamKind kind = ParamKind::reset;
  double value = 0.0;  // threshold_m, stiffness_n_per_m, damping_n_s_per_m or change_ramp_s
  ModelChange model;   // kind == model
};

// what the loop applied, back to the node for its ack and task event (trivially copyable)
struct ParamApplied {
  std::uint64_t request_id = 0;
  ParamKind kind = ParamKind::reset;
  std::int64_t time_ns = 0;  // when it was applied, on the node's monotonic clock
  std::uint64_t step = 0;    // the simulator's step that first uses it (1 = the first after activate)
};

// the accepted names, without the node prefix, in the order of the header comment
const std::vector<std::string>& param_names();

// the answer to one request: the change to apply, or why it was refused
struct ParamPlan {
  bool accepted = false;
  ParamChange change;
  std::string reason;  // refused: the problem and the fix
};

class ParamPlanner {
 public:
  // a mirror of `simulator` as configured: its model (rate included) and computer model. The
  // stability envelope is fixed here: K T/2 + B of the device passivity bound (all body
  // points in contact, whatever the computer model) may not exceed the larger of the
  // device's damping b and its value for the scene as loaded (which `enact check` accepted).
  // Without a device profile b is 0: stiffness and damping can only go down.
  explicit ParamPlanner(const Simulator& simulator);

  // mirror the simulator again as it is now (restored from a keyframe: the parameters then in
  // force); the envelope stays the one of the scene as loaded
  void follow(const Simulator& simulator);

  // checks `name` (without the node prefix) = value. Accepted: the mirror is updated as the
  // simulator will be once it applies the change. Never throws on bad input.
  ParamPlan plan(const std::string& name, const ParamValue& value, std::uint64_t request_id);

  // the mirror's computer model, and the body's contact stiffness and damping (its first pair)
  const haptics::ComputerModel& computer_model() const { return cm_; }
  double stiffness_n_per_m() const;
  double damping_n_s_per_m() const;
  // the largest K T/2 + B live changes may reach (N s/m)
  double passivity_envelope_n_s_per_m() const { return envelope_; }

 private:
  ParamPlan check_contact(ParamKind kind, double value, std::uint64_t request_id);

  physics::Model model_;
  haptics::ComputerModel cm_;
  int grid_masses_ = 0;
  double device_damping_ = 0.0;
  double envelope_ = 0.0;
};

// the passivity demand K T/2 + B of the exploratory body with every body point feeding the
// device and every body contact pair at the given stiffness and damping (N s/m)
double body_passivity_demand(physics::Model model, double stiffness_n_per_m, double damping_n_s_per_m);

// the largest K T/2 + B live stiffness and damping changes may reach on `model` as loaded:
// the larger of its device's damping b (0 without a device profile) and the body's demand
// with every body point feeding the device (any computer model may be switched to live) at
// the scene's own stiffness and damping. `enact check`, the viewer and every refusal give
// this one figure
double passivity_envelope(const physics::Model& model);

// a point of the exploratory body (proxy 0's): the points live changes act on
bool is_body_point(const physics::Model& model, int point);

// sets stiffness and damping of every contact pair of proxy 0's points; allocates nothing
void set_body_contacts(physics::Model& model, std::optional<double> stiffness_n_per_m, std::optional<double> damping_n_s_per_m);

// the loop's copy of a computer model, and back
ModelChange to_change(const haptics::ComputerModel& cm);
void assign(haptics::ComputerModel& cm, const ModelChange& change);

}  // namespace enact::sim
