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
//   each live number    a row of live_numbers() (threshold_m, stiffness_n_per_m, ...): its
//                       range, unit, help, planning and application declared there once
//   reset               command: model, pins and task back to their start (a new trial)
//   reposition          command: the subject is put back at the start; contact memory is
//                       cleared, the trial goes on
//   trial               "start" (or true): a new trial from now; "stop" (or false): the
//                       trial ends, its metrics are kept
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/haptics/computer_model.h"
#include "core/haptics/tactile.h"
#include "core/physics/model.h"
#include "core/sim/reengage.h"
#include "core/task/bridge_task.h"

namespace enact::sim {

// the passivity demand K T/2 + B of the exploratory body with every body point feeding the
// device and every body contact pair at a stiffness and damping (N s/m): sums of the body's
// elements, so linear in both; found once per scene, then a request is checked by arithmetic
struct PassivityDemand {
  double at_zero = 0.0, per_n_per_m = 0.0, per_n_s_per_m = 0.0;
  double at(double stiffness_n_per_m, double damping_n_s_per_m) const {
    return at_zero + per_n_per_m * stiffness_n_per_m + per_n_s_per_m * damping_n_s_per_m;
  }
};
PassivityDemand body_passivity_demand(const physics::Model& model);

class Simulator;
class ParamPlanner;

// the most rows live_numbers() may have
inline constexpr std::size_t kMaxLiveNumbers = 16;

struct SimParams {
  std::string scene;               // scene file (YAML)
  double rate_hz = 0.0;            // 0: the scene's rate_hz
  std::string model = "CM1";       // computer model: preset name or YAML file
  haptics::TactileParams tactile;  // pin frame down-sampling
  task::TaskParams task;           // fall rule and completion
  bool force = false;              // run a scene that fails the stability check anyway
  // live changes never jolt: the force felt before a change blends into the new setting's over
  // this long (longer when the device profile's max_force_step_n_per_ms needs it)
  double change_ramp_s = 0.05;
  // after a live change of the force law (a model, threshold or stiffness, a reset), the body's
  // points come back out of what they sank into at most this fast (the bridge: 17 points at 6000 N/m, about 1 N/ms; 50 mm/s
  // launched the scripted hand off the top in a hostile burst, and it fell back hard); the
  // device profile's force step limit may make it slower still
  double reentry_speed_m_per_s = 0.01;
  // after a cut of the force path (its start, a watchdog episode, a late tick) or a late
  // sample held, the body returns to the device over this time (Reengagement)
  double reengage_s = kReengageDefault_s;
  // a live number's value from the start (by its row of live_numbers(), those without a
  // field here): none, the scene's or the computer model's
  std::array<std::optional<double>, kMaxLiveNumbers> live_at_start{};
};


// what a live number acts on: the simulator's model, computer model and parameters, or the
// planner's mirror of them
struct LiveTarget {
  physics::Model& model;
  haptics::ComputerModel& cm;
  SimParams& params;
};

// how a live number's change meets the force law (Simulator::apply: no jolt)
enum class LawChange : std::uint8_t {
  none,    // the force law stays (a blend time)
  always,  // it changes: the felt forces are kept and blend into the new law's
  if_new,  // it re-applies the computer model: a change when the value is new or a change still settles
};

// a numeric live parameter of the simulator, declared once: the parameter table's row
// (graph::sim_bindings), the planner's check, the ack, the parameter board's mirror, the
// viewer's field and the choices of a discrimination experiment all come from it. Adding one
// is a row here (and its line in docs/parameters.md)
struct LiveNumber {
  const char* name;  // with its unit (the table's rules: _m, _n_per_m, _s ...)
  double min, max;   // accepted range, inclusive (max: infinity for none)
  const char* doc;   // one line, for the table and docs
  const char* example;  // a value for the fix of a refusal
  LawChange law;
  double SimParams::*at_start;  // given at start into this field of SimParams (nullptr: into SimParams::live_at_start)
  double (*get)(const physics::Model&, const haptics::ComputerModel&, const SimParams&);  // the value in force
  void (*set)(LiveTarget&, double);  // between two steps on the loop: allocates nothing
  // beyond the range, off the loop: "" accepts, else the problem and its fix
  std::string (*check)(const ParamPlanner&, double) = nullptr;
};

// the live numbers, at most kMaxLiveNumbers
const std::vector<LiveNumber>& live_numbers();
// the row named `name` (nullptr: none)
const LiveNumber* find_live_number(const std::string& name);

// the most changes planned but not applied yet at any time (the capacity of a loop's queues)
inline constexpr std::size_t kMaxParamsInFlight = 16;

// the value of a request as sent on the bus: at most one of them is set
struct ParamValue {
  std::optional<double> number;
  std::optional<std::string> text;
  std::optional<bool> flag;
};

// a number: a row of live_numbers(), ParamChange::number
enum class ParamKind : std::uint8_t { model, number, reset, reposition, trial_start, trial_stop };

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
  std::uint8_t number = 0;  // kind == number: its row of live_numbers()
  double value = 0.0;       // kind == number: the value
  ModelChange model;        // kind == model
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

  // the mirror's computer model, and the value in force of a live number
  const haptics::ComputerModel& computer_model() const { return cm_; }
  const physics::Model& model() const { return model_; }
  double value(const LiveNumber& number) const;
  double stiffness_n_per_m() const;
  double damping_n_s_per_m() const;
  // the refusal of a body contact's stiffness or damping at `value` ("" when the loop stays
  // stable: the passivity envelope, a deformable body's integrator bound)
  std::string contact_refusal(bool stiffness, double value) const;
  // the largest K T/2 + B live changes may reach (N s/m)
  double passivity_envelope_n_s_per_m() const { return envelope_; }

 private:
  LiveTarget mirror() { return {model_, cm_, params_}; }

  physics::Model model_;
  haptics::ComputerModel cm_;
  SimParams params_;
  int grid_masses_ = 0;
  double device_damping_ = 0.0;
  PassivityDemand demand_;
  double envelope_ = 0.0;
};


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
