#pragma once
// Filling the bus messages from the components' state, one place for every node.
#include <cstdint>
#include <string>

#include "core/devices/device.h"
#include "core/rt/loop_stats.h"
#include "core/sim/keyframe.h"
#include "core/sim/simulator.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/sim_keyframe.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"

namespace enact::graph {

void set(msgs::Vec3& out, const math::Vec3& v);
math::Vec3 get(const msgs::Vec3& v);

// device fault bits (devices::DeviceFault) as the bus's DeviceFault bits
std::uint32_t device_faults(std::uint32_t faults);
// whether a device state with these bus fault bits says the force path was cut (the
// driver's watchdog, a failed transfer): the simulator then re-synchronises its body with
// the device (enact-sim, enact-rt and enact resim alike)
bool force_path_cut(std::uint32_t bus_faults);

void fill(msgs::DeviceState& m, const devices::ForceSample& s);
void fill(msgs::ForceCommand& m, std::uint64_t answered_seq, const math::Vec3& force_n, bool model_fault);
// pins as levels 0 / 1 (the repeated field is resized once, then overwritten)
void fill(msgs::TactileFrame& m, int rows, int cols, std::uint32_t pins);
// what the pins show, and how they move where the device knows it (motion: nullptr for none)
void fill(msgs::TactileShown& m, int rows, int cols, const float* levels, std::uint64_t frame_seq, const devices::PinMotion* motion);
// the pins' motion a TactileShown carries, into out: false when it carries none (or a bad one)
bool get(const msgs::TactileShown& m, devices::PinMotion& out);
// the simulator's body, per-mass contact forces and contacts, pins, resultant, task state
// what the scene shows at one step, copied out of the simulator without allocating (the
// real-time thread takes it, the publisher thread sends it)
struct SceneSnapshot {
  std::int64_t time_ns = 0;  // on the graph's clock (the device's: Simulator::origin_ns plus the model's time)
  math::Vec3 body_m;
  int masses = 0;            // grid masses (pins), at most 32
  math::Vec3 contact_force_n[32];
  std::uint32_t in_contact = 0;  // bit i: grid mass i touches
  std::uint32_t pins = 0;
  math::Vec3 force_n;     // sent to the device
  bool on_top = false;
  double progress = 0.0;
};
void snapshot(const sim::Simulator& s, std::uint32_t pins, const math::Vec3& force_n, SceneSnapshot& out);
void fill(msgs::SceneState& m, const SceneSnapshot& s, const std::string& model);
// a keyframe of the simulator running `model` (its body's position, the trial so far on the
// device clock, the packed memory into the message's reused bytes)
void fill(msgs::SimKeyframe& m, const sim::Keyframe& k, const physics::Model& model);
// a task event; false when there is none
bool fill(msgs::TaskEvent& m, const task::TaskEvent& e, const std::string& condition);
void fill(msgs::NodeStatus& m, const std::string& node, const rt::LoopSummary& loop, std::uint64_t faults, const std::string& last_fault);

}  // namespace enact::graph
