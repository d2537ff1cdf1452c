#include "core/graph/components.h"

#include "core/config/yaml.h"
#include "core/devices/safety.h"
#include "core/devices/simulated_force.h"
#include "core/devices/simulated_tactile.h"

namespace enact::graph {
namespace {

void only_simulated(const Params& p) {
  const std::string device = p.text("device", "simulated");
  if (device != "simulated") {
    throw config::Error("device '" + device + "' is not available\n  fix: use device=simulated (USB backends come with the devices work)");
  }
}

}  // namespace

const std::vector<std::string> kSimParams{"scene", "rate_hz", "model", "tactile_period_s", "tactile_mode", "force",
                                          "min_fall_s", "min_recovery_s", "end_progress"};
const std::vector<std::string> kForceParams{"device", "profile", "hand_path", "subject", "subject_seed", "noise_seed", "start_m",
                                            "hand_stiffness_n_per_m", "hand_damping_n_s_per_m", "watchdog_s", "ramp_s"};
const std::vector<std::string> kTactileParams{"device", "rows", "cols", "rise_time_s"};

sim::SimParams sim_params(const Params& p) {
  sim::SimParams s;
  s.scene = p.text("scene", "");
  if (s.scene.empty()) throw config::Error("the simulator needs a scene\n  fix: --param scene=launch/scenes/bridge.yaml");
  s.rate_hz = p.number("rate_hz", 0.0);
  s.model = p.text("model", s.model);
  s.tactile.period_s = p.number("tactile_period_s", s.tactile.period_s);
  s.tactile.mode = haptics::parse_tactile_mode(p.text("tactile_mode", "sample"));
  s.force = p.flag("force", false);
  s.task.min_fall_s = p.number("min_fall_s", s.task.min_fall_s);
  s.task.min_recovery_s = p.number("min_recovery_s", s.task.min_recovery_s);
  s.task.end_progress = p.number("end_progress", s.task.end_progress);
  return s;
}

std::unique_ptr<devices::ForceDevice> make_force_device(const Params& p) {
  only_simulated(p);
  devices::SimulatedForceParams f;
  f.profile = p.text("profile", f.profile);
  f.hand_path = p.text("hand_path", "");
  f.subject = p.text("subject", "");
  f.subject_seed = static_cast<std::uint64_t>(p.integer("subject_seed", 0));
  f.noise_seed = static_cast<std::uint64_t>(p.integer("noise_seed", 0));
  f.start_m = p.vec3("start_m", f.start_m);
  f.hand_stiffness_n_per_m = p.number("hand_stiffness_n_per_m", f.hand_stiffness_n_per_m);
  f.hand_damping_n_s_per_m = p.number("hand_damping_n_s_per_m", f.hand_damping_n_s_per_m);
  devices::SafetyParams s;
  s.watchdog_s = p.number("watchdog_s", s.watchdog_s);
  s.ramp_s = p.number("ramp_s", s.ramp_s);
  auto device = std::make_unique<devices::SafeForceDevice>(std::make_unique<devices::SimulatedForceDevice>(f), s);
  device->configure();
  return device;
}

std::unique_ptr<devices::TactileDevice> make_tactile_device(const Params& p) {
  only_simulated(p);
  devices::SimulatedTactileParams t;
  t.rows = p.integer("rows", t.rows);
  t.cols = p.integer("cols", t.cols);
  t.rise_time_s = p.number("rise_time_s", t.rise_time_s);
  auto device = std::make_unique<devices::SimulatedTactileDevice>(t);
  device->configure();
  return device;
}

}  // namespace enact::graph
