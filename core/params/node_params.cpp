#include "core/params/node_params.h"

#include <algorithm>
#include <filesystem>

#include "core/launch/check.h"

#include "core/config/format.h"
#include "core/config/share.h"
#include "core/devices/falcon/falcon_device.h"
#include "core/devices/inverse3/inverse3_device.h"
#include "core/devices/metec/metec_device.h"
#include "core/devices/safety.h"
#include "core/devices/simulated_force.h"
#include "core/devices/simulated_tactile.h"
#include "core/params/device_config.h"
#include "core/params/param_binding.h"
#include "core/devices/device_profile.h"
#include "core/rt/scheduler.h"
#include "core/sim/reengage.h"
#include "core/sim/simulator.h"

// the declarations name only the fields they set: every other one has its default
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace enact::graph {
namespace {

using config::number;

constexpr const char* kAttachDoc =
    "attach endpoint (default: the graph that launched it, else the only one running; keys: $ENACT_KEY, $ENACT_SERVER_KEY)";
constexpr double kInf = std::numeric_limits<double>::infinity();

// the defaults are the components' own (their structs' initial values)
const sim::SimParams kSim{};
const devices::SimulatedForceParams kHand{};

// what a loop process shares (a config with a LoopConfig `loop`): enact-ffd, enact-rt
template <class Config>
void bind_loop(ParamBindings<Config>& b) {
  b.field([](Config& c) -> double& { return c.loop.rate_hz; }, {.name = "rate_hz", .min = rt::kMinRate_hz, .max = rt::kMaxRate_hz, .doc = "loop rate"})
      .field([](Config& c) -> double& { return c.loop.spin_us; },
             {.name = "spin_us", .min = -1, .doc = "spin on the clock for the last microseconds before each tick (-1: sized from this machine's probe, enact doctor)"})
      .field([](Config& c) -> double& { return c.loop.duration_s; }, {.name = "duration_s", .min = 0, .doc = "stop after this long (0: until SIGINT/SIGTERM)"})
      .field([](Config& c) -> bool& { return c.loop.lock_memory; }, {.name = "lock_memory", .doc = "mlockall the process"})
      .field([](Config& c) -> int& { return c.loop.fifo_priority; }, {.name = "fifo_priority", .min = 0, .max = 99, .doc = "SCHED_FIFO priority of the loop (0: normal scheduling)"});
}

// the ffd <-> sim hop, declared by both ends
ParamSpec loop_transport_decl() {
  return {.name = "loop_transport", .type = ParamType::choice, .choices = {"auto", "local", "zeromq"},
          .doc = "the ffd <-> sim hop: local (a same-host link through shared memory the loop threads read themselves: about the machine's pipe floor), zeromq (the bus), "
                 "auto (local: a graph's nodes share one host); observers see every message either way"};
}

ParamTable sim_node_table() {
  ParamTable t = sim_table();
  const ParamTable& own = sim_node_bindings().table();
  t.insert(t.end(), own.begin(), own.end());
  return t;
}

ParamTable ffd_node_table() {
  const ParamTable& own = ffd_node_bindings().table();
  const ParamTable device = force_table();
  return join({&own, &device});
}

ParamTable tactile_node_table() {
  const ParamTable& own = tactile_node_bindings().table();
  const ParamTable device = tactile_table();
  return join({&own, &device});
}

ParamTable rt_table() { return rt_bindings().table(); }

// the value of a launch parameter where it was written: its line, or the --arg it came from
std::string where(const launch::NodeSpec& n, const launch::Param& p) { return p.source.empty() ? n.source : p.source; }

// the problems of `params` against `table`, for node (or component) `owner` of `n`
void check_against(const launch::NodeSpec& n, const std::string& owner, const std::vector<launch::Param>& params, const ParamTable& table,
                   const std::vector<std::string>& components, std::vector<std::string>& problems) {
  for (const launch::Param& p : params) {
    const std::string at = where(n, p) + ": node '" + owner + "': parameter '" + p.name + "' ";
    const ParamSpec* s = find_spec(table, p.name);
    const std::size_t dot = p.name.find('.');
    if (!s && dot != std::string::npos && std::find(components.begin(), components.end(), p.name.substr(0, dot)) != components.end()) continue;
    if (!s || !s->at_start) problems.push_back(at + unknown_problem(table, p.name, owner));
    else if (const auto problem = value_problem(*s, p.value)) problems.push_back(at + *problem);
  }
}

// a container's or enact-sim's component list: the problem with it at the line of the entry
// it is about (of the node for the list as a whole); a stage from a plugin library is left to
// the node's own --check, which loads the library
void check_components(const launch::NodeSpec& n, std::vector<std::string>& problems) {
  auto line_of = [&](const launch::ComponentSpec& c) {
    return c.line > 0 ? n.source.substr(0, n.source.rfind(':')) + ":" + std::to_string(c.line) : n.source;
  };
  std::vector<std::pair<std::string, std::string>> list;
  std::vector<const launch::ComponentSpec*> listed;
  for (const launch::ComponentSpec& c : n.components) {
    if (!c.library.empty() && !std::filesystem::is_regular_file(c.library)) {
      problems.push_back(line_of(c) + ": node '" + n.name + "': component '" + c.name + "': there is no plugin library '" + c.library +
                         "'\n  fix: build it (" + config::shipped("docs/components.md") + "), or correct the path (relative to where enact runs; $(dirname) is the launch file's folder)");
    }
    if (!c.library.empty() && !find_component_kind(c.plugin)) continue;
    list.emplace_back(c.name, c.plugin);
    listed.push_back(&c);
  }
  const auto problem = n.container ? component_list_problem(list) : stage_list_problem(n.path, list);
  if (!problem) return;
  const std::string at = problem->entry < listed.size() ? line_of(*listed[problem->entry]) : n.source;
  problems.push_back(at + ": node '" + n.name + "': " + problem->text);
}

}  // namespace

// the tactile frame's mode, a choice of two words
template <>
struct ParamCodec<haptics::TactileMode> {
  static constexpr ParamType type = ParamType::choice;
  static std::string text(haptics::TactileMode m) { return m == haptics::TactileMode::any ? "any" : "sample"; }
  static haptics::TactileMode read(const Params& p, const std::string& name) { return haptics::parse_tactile_mode(p.text(name)); }
};

const ParamBindings<sim::SimParams>& sim_bindings() {
  using S = sim::SimParams;
  static const ParamBindings<S> b = [] {
    ParamBindings<S> t;
    t.field(&S::scene, {.name = "scene", .doc = "scene file (YAML)", .required = true})
        .field(&S::rate_hz, {.name = "rate_hz", .min = 0, .max = rt::kMaxRate_hz, .doc = "model rate (0: the scene's; should match the FFD's)"})
        .field(&S::model, {.name = "model", .doc = "computer model: CM0 CM1 CM2 CM3 P T PT or a YAML file", .live = true})
        .field([](S& s) -> double& { return s.tactile.period_s; }, {.name = "tactile_period_s", .min = 0, .doc = "tactile frame period (the cells' rise time)"})
        .field([](S& s) -> haptics::TactileMode& { return s.tactile.mode; },
               {.name = "tactile_mode", .choices = {"sample", "any"}, .doc = "a frame samples its last step, or any contact since the last frame"})
        .field(&S::force, {.name = "force", .doc = "run a scene that fails the stability check anyway"})
        .field([](S& s) -> double& { return s.task.min_fall_s; }, {.name = "min_fall_s", .min = 0, .doc = "a loss of contact shorter than this is not a fall"})
        .field([](S& s) -> double& { return s.task.min_recovery_s; },
               {.name = "min_recovery_s", .min = 0, .doc = "contact regained for less than this does not end a fall"})
        .field([](S& s) -> double& { return s.task.end_progress; }, {.name = "end_progress", .min = 0, .max = 1, .doc = "progress that completes the bridge"})
        .field(&S::reengage_s, {.name = "reengage_s", .min = 0,
                   .doc = "after a cut of the force path (its start, a watchdog episode, a late tick) or a late sample held, the body returns to the device over this time"})
        .field(&S::reentry_speed_m_per_s, {.name = "reentry_speed_m_per_s", .min = 0, .above_min = true, .doc = "after a live change of the force law, the body comes back out of the objects at most this fast"})
        .declared({.name = "reset", .type = ParamType::command, .doc = "model, pins and task back to their start: a new trial", .live = true, .at_start = false})
        .declared({.name = "reposition", .type = ParamType::command, .doc = "the subject is put back at the start; the trial goes on", .live = true, .at_start = false})
        .declared({.name = "trial", .type = ParamType::command, .choices = {"start", "stop"}, .doc = "start: a new trial from now; stop: the trial ends", .live = true, .at_start = false});
    // the live numbers, each declared once with its range, planning and application (sim/params.h)
    // (given at start too: into their field of SimParams, or its live_at_start, empty: the scene's)
    for (std::size_t i = 0; i < sim::live_numbers().size(); ++i) {
      const sim::LiveNumber& n = sim::live_numbers()[i];
      const ParamSpec spec{.name = n.name, .min = n.min, .max = n.max, .doc = n.doc, .live = true};
      if (n.at_start) t.field(n.at_start, spec);
      else t.field([i](S& s) -> std::optional<double>& { return s.live_at_start[i]; }, spec);
    }
    return t;
  }();
  return b;
}

const ParamTable& sim_table() { return sim_bindings().table(); }

sim::SimParams sim_params(const Params& p) { return sim_bindings().read(p); }

const ParamBindings<ForceConfig>& force_bindings() {
  using F = ForceConfig;
  static const ParamBindings<F> b = [] {
    ParamBindings<F> t;
    t.field(&F::device, {.name = "device", .type = ParamType::choice, .choices = {"simulated", "falcon", "dhd", "hd", "inverse3"},
                         .doc = "simulated; a Novint Falcon over USB; a Force Dimension device (DHD SDK); an OpenHaptics device such as a 3D Systems Touch (HD "
                                "API); a Haply Inverse3 (Inverse Service)"})
        .field([](F& c) -> std::string& { return c.hand.profile; },
               {.name = "profile", .type = ParamType::choice, .choices = devices::device_profile_names(),
                .doc = "device profile (simulated device; dhd: default omega3; hd: default touch; inverse3: default inverse3)"})
        .field([](F& c) -> std::string& { return c.hand.hand_path; }, {.name = "hand_path", .doc = "CSV (t_s,x_m,y_m,z_m) the scripted hand tracks (empty: it holds start_m)"})
        .field([](F& c) -> std::string& { return c.hand.subject; }, {.name = "subject", .doc = "a virtual subject's file (YAML) holds the device instead"})
        .field([](F& c) -> std::uint64_t& { return c.hand.subject_seed; }, {.name = "subject_seed", .min = 0, .doc = "the virtual subject's traits"})
        .field([](F& c) -> std::uint64_t& { return c.hand.noise_seed; }, {.name = "noise_seed", .min = 0, .doc = "the virtual subject's motor noise"})
        .declared({.name = "start_m", .type = ParamType::vec3,
                   .doc = "start position of the end-effector (empty: the body's position_m in `start_scene`, else " + ParamCodec<math::Vec3>::text(kHand.start_m) + ")"})
        .field(&F::start_scene, {.name = "start_scene", .doc = "the graph's scene file: the end-effector starts where its body is (position_m) unless start_m is given"})
        .field([](F& c) -> double& { return c.hand.hand_stiffness_n_per_m; }, {.name = "hand_stiffness_n_per_m", .min = 0, .doc = "the hand's grip stiffness"})
        .field([](F& c) -> double& { return c.hand.hand_damping_n_s_per_m; }, {.name = "hand_damping_n_s_per_m", .min = 0, .doc = "the hand's grip damping"})
        .field([](F& c) -> double& { return c.safety.watchdog_s; },
               {.name = "watchdog_s", .min = 0, .above_min = true, .doc = "longest time without a command before the force ramps down"})
        .field([](F& c) -> double& { return c.safety.ramp_s; }, {.name = "ramp_s", .min = 0, .doc = "ramp from the last command to zero"})
        .field([](F& c) -> double& { return c.safety.reengage_s; }, {.name = "reengage_s", .min = 0, .doc = "ramp from zero back to the commands after an interruption"})
        .field(&F::transport, {.name = "transport", .type = ParamType::choice, .choices = {"usb", "emulator"},
                               .doc = "falcon: the machine's USB, or the Falcon emulator; inverse3: the Inverse Service (usb), or its emulator"})
        .field([](F& c) -> std::string& { return c.falcon.serial; }, {.name = "serial", .doc = "falcon: the serial number (empty: the first found)"})
        .field([](F& c) -> std::string& { return c.falcon.firmware; }, {.name = "firmware", .doc = "falcon: the firmware file to upload when none runs"})
        .field([](F& c) -> double& { return c.falcon.homing_timeout_s; },
               {.name = "homing_timeout_s", .min = 0, .above_min = true, .doc = "falcon: how long the user has to home the grip"})
        .field([](F& c) -> double& { return c.falcon.max_force_n; }, {.name = "max_force_n", .min = 0, .max = 9, .above_min = true, .doc = "falcon: the force is clamped to this"})
        .field(&F::library, {.name = "library", .doc = "dhd, hd: the vendor's library, a file name or path (default libdhd.so, libHD.so)"})
        .field(&F::device_name, {.name = "device_name", .doc = "hd: the device's name in Touch Setup (empty: the default device)"})
        .field([](F& c) -> int& { return c.inverse3.port; }, {.name = "port", .min = 1, .max = 65535, .doc = "inverse3: the Inverse Service's simulation channel (WebSocket)"})
        .field([](F& c) -> int& { return c.inverse3.events_port; }, {.name = "events_port", .min = 0, .max = 65535, .doc = "inverse3: the Inverse Service's events channel (0: none)"})
        .field([](F& c) -> std::string& { return c.inverse3.device_id; }, {.name = "device_id", .doc = "inverse3: the device's id in the service (empty: the first listed)"})
        .field([](F& c) -> math::Vec3& { return c.inverse3.origin_m; }, {.name = "origin_m", .doc = "inverse3: the point of the service's frame that is enact's origin"});
    return t;
  }();
  return b;
}

const ParamTable& force_table() { return force_bindings().table(); }

const ParamBindings<SimNodeConfig>& sim_node_bindings() {
  static const ParamBindings<SimNodeConfig> b = [] {
    ParamBindings<SimNodeConfig> out;
    out.field(&SimNodeConfig::loop_transport, loop_transport_decl())
        .field(&SimNodeConfig::ffd_node, {.name = "ffd_node", .doc = "the FFD driver's node name (its ffd/state)"})
        .field(&SimNodeConfig::scene_rate_hz, {.name = "scene_rate_hz", .min = 0, .above_min = true, .doc = "sim/scene rate (decimated)"})
        .field(&SimNodeConfig::observers, {.name = "observers", .min = 0, .max = 100, .doc = "wait up to 60 s for this many observers of ffd/force before answering"});
    return out;
  }();
  return b;
}

const ParamBindings<FfdNodeConfig>& ffd_node_bindings() {
  static const ParamBindings<FfdNodeConfig> b = [] {
    ParamBindings<FfdNodeConfig> out;
    bind_loop(out);
    out.field(&FfdNodeConfig::loop_transport, loop_transport_decl())
        .field(&FfdNodeConfig::sim_node, {.name = "sim_node", .doc = "the simulator's node name (its ffd/force)"})
        .field(&FfdNodeConfig::tactile_node, {.name = "tactile_node", .doc = "the tactile driver's node name (a virtual subject feels its tactile/shown)"})
        .field(&FfdNodeConfig::observers, {.name = "observers", .min = 0, .max = 100, .doc = "wait up to 60 s for this many observers of ffd/state besides the simulator"});
    return out;
  }();
  return b;
}

const ParamBindings<RtConfig>& rt_bindings() {
  static const ParamBindings<RtConfig> b = [] {
    ParamBindings<RtConfig> out;
    bind_loop(out);
    out.declared({.name = "cpus", .type = ParamType::integer, .fallback = "", .min = 0, .max = 4095, .doc = "the CPU of the loop thread (empty: any)"})
        .field(&RtConfig::scene_rate_hz, {.name = "scene_rate_hz", .min = 0, .above_min = true, .doc = "sim/scene rate (decimated)"})
        .field(&RtConfig::shown_rate_hz, {.name = "shown_rate_hz", .min = 0, .above_min = true, .doc = "tactile/shown rate"})
        .field(&RtConfig::observers, {.name = "observers", .min = 0, .max = 100, .doc = "wait up to 60 s for this many observers of ffd/state before the loop starts"});
    return out;
  }();
  return b;
}

const ParamBindings<LoggerConfig>& logger_bindings() {
  static const ParamBindings<LoggerConfig> b = [] {
    ParamBindings<LoggerConfig> out;
    out.field(&LoggerConfig::output, {.name = "output", .doc = "file (with splitting: NAME_000.mcap, NAME_001.mcap, ...)"})
        .field(&LoggerConfig::topics, {.name = "topics", .doc = "comma-separated topics to keep (empty: every topic)"})
        .field(&LoggerConfig::regex, {.name = "regex", .doc = "only topics the regular expression matches"})
        .field(&LoggerConfig::exclude, {.name = "exclude", .doc = "no topic the regular expression matches"})
        .field(&LoggerConfig::compression, {.name = "compression", .type = ParamType::choice, .choices = {"zstd", "lz4", "none"}, .doc = "chunk compression"})
        .field(&LoggerConfig::chunk_duration_s, {.name = "chunk_duration_s", .min = 0, .above_min = true, .doc = "a chunk reaches the file at least this often (the most a kill -9 loses)"})
        .field(&LoggerConfig::split_size_mb, {.name = "split_size_mb", .min = 0, .doc = "start a new file past this size (0: never)"})
        .field(&LoggerConfig::split_duration_s, {.name = "split_duration_s", .min = 0, .doc = "start a new file after this long (0: never)"})
        .field(&LoggerConfig::attach, {.name = "attach", .doc = kAttachDoc})
        .field(&LoggerConfig::wait_s, {.name = "wait_s", .min = 0, .doc = "how long to wait for the graph"});
    return out;
  }();
  return b;
}

const ParamBindings<FoxgloveConfig>& foxglove_bindings() {
  static const ParamBindings<FoxgloveConfig> b = [] {
    ParamBindings<FoxgloveConfig> out;
    out.field(&FoxgloveConfig::port, {.name = "port", .min = 0, .max = 65535, .doc = "WebSocket port (0: any free port)"})
        .field(&FoxgloveConfig::host, {.name = "host", .doc = "where it listens (clients may publish param/set only on loopback)"})
        .field(&FoxgloveConfig::max_rate_hz, {.name = "max_rate_hz", .min = 0, .above_min = true, .doc = "per client, on topics that run faster"})
        .field(&FoxgloveConfig::attach, {.name = "attach", .doc = kAttachDoc});
    return out;
  }();
  return b;
}

const ParamBindings<TactileNodeConfig>& tactile_node_bindings() {
  static const ParamBindings<TactileNodeConfig> b = [] {
    ParamBindings<TactileNodeConfig> out;
    out.field(&TactileNodeConfig::sim_node, {.name = "sim_node", .doc = "the simulator's node name (its tactile/frame)"})
        .field(&TactileNodeConfig::shown_rate_hz, {.name = "shown_rate_hz", .min = 0, .above_min = true, .doc = "tactile/shown rate"})
        .field(&TactileNodeConfig::watchdog_s, {.name = "watchdog_s", .min = 0, .above_min = true, .doc = "every pin down while no frame came for this long"});
    return out;
  }();
  return b;
}

const ParamBindings<TactileConfig>& tactile_bindings() {
  using T = TactileConfig;
  static const ParamBindings<T> b = [] {
    ParamBindings<T> t;
    t.field(&T::device, {.name = "device", .type = ParamType::choice, .choices = {"simulated", "metec"}, .doc = "simulated, or Metec Braille cells over USB"})
        .field([](T& c) -> int& { return c.cells.rows; }, {.name = "rows", .min = 1, .max = 32, .doc = "pin rows"})
        .field([](T& c) -> int& { return c.cells.cols; }, {.name = "cols", .min = 1, .max = 32, .doc = "pin columns (rows x cols <= 32)"})
        .field([](T& c) -> double& { return c.cells.rise_time_s; }, {.name = "rise_time_s", .min = 0, .above_min = true, .doc = "the cells' full stroke"})
        .field(&T::transport, {.name = "transport", .type = ParamType::choice, .choices = {"usb", "emulator"}, .doc = "metec: the machine's USB, or the Metec emulator"})
        .field([](T& c) -> std::string& { return c.metec.serial; }, {.name = "serial", .doc = "metec: the serial number (empty: the first found)"})
        .field([](T& c) -> int& { return c.metec.first_cell; }, {.name = "first_cell", .min = 0, .doc = "metec: the cell under pin columns 0 and 1"});
    return t;
  }();
  return b;
}

const ParamTable& tactile_table() { return tactile_bindings().table(); }

const ParamTable& logger_component_table() { return logger_bindings().table(); }
const ParamTable& foxglove_component_table() { return foxglove_bindings().table(); }

namespace {
std::vector<ComponentKind>& kinds() {
  static std::vector<ComponentKind> kinds{
      {"sim", ComponentRole::model, "simulator", &sim_table, true},
      {"ffd", ComponentRole::force_device, "force-feedback device", &force_table, true},
      {"tactile", ComponentRole::tactile_device, "tactile display", &tactile_table, false},
      {"logger", ComponentRole::observer, "logger (an MCAP recording of the graph)", &logger_component_table, false},
      {"foxglove", ComponentRole::observer, "Foxglove bridge (WebSocket)", &foxglove_component_table, false},
  };
  return kinds;
}
}  // namespace

const std::vector<ComponentKind>& component_kinds() { return kinds(); }

bool add_component_kind(const ComponentKind& kind) {
  if (find_component_kind(kind.plugin)) return false;
  kinds().push_back(kind);
  return true;
}

const ComponentKind* find_component_kind(const std::string& plugin) {
  for (const ComponentKind& k : component_kinds()) {
    if (plugin == k.plugin) return &k;
  }
  return nullptr;
}

const ParamTable* component_table(const std::string& plugin) {
  const ComponentKind* kind = find_component_kind(plugin);
  return kind ? &kind->table() : nullptr;
}

std::optional<ComponentProblem> component_list_problem(const std::vector<std::pair<std::string, std::string>>& components) {
  std::string plugins;
  for (const ComponentKind& k : component_kinds()) plugins += std::string(plugins.empty() ? "" : ", ") + k.plugin + " (" + k.what + ")";
  const std::string one_each = "enact-rt's one tick reads one force device, steps one model and, if it has one, writes one tactile display: of " + plugins +
                               " one each of the first three, the tactile display optional, observers (logger, foxglove) and stages from plugin libraries as many as wanted";
  std::vector<std::size_t> first(component_kinds().size(), static_cast<std::size_t>(-1));
  for (std::size_t i = 0; i < components.size(); ++i) {
    const auto& [name, plugin] = components[i];
    const ComponentKind* kind = find_component_kind(plugin);
    if (!kind) {
      return ComponentProblem{i, "component '" + name + "': unknown plugin '" + plugin + "'\n  fix: use one of " + plugins +
                                     "; a stage of your own: give its plugin library (library: PATH in the launch file, --library=PATH to enact-rt)"};
    }
    std::size_t& seen = first[static_cast<std::size_t>(kind - component_kinds().data())];
    if (seen != static_cast<std::size_t>(-1) && kind->role != ComponentRole::observer && kind->role != ComponentRole::stage) {
      return ComponentProblem{i, "components '" + components[seen].first + "' and '" + name + "' are both a " + kind->what + " (plugin " + plugin + ")\n  fix: keep one; " + one_each};
    }
    seen = i;
  }
  for (std::size_t k = 0; k < first.size(); ++k) {
    const ComponentKind& kind = component_kinds()[k];
    if (first[k] != static_cast<std::size_t>(-1) || !kind.required) continue;
    return ComponentProblem{static_cast<std::size_t>(-1), std::string("it has no ") + kind.what + " (plugin " + kind.plugin + ")\n  fix: add {name: " + kind.plugin +
                                                              ", plugin: " + kind.plugin + "} to its component list; " + one_each};
  }
  return std::nullopt;
}

std::optional<ComponentProblem> stage_list_problem(const std::string& exec, const std::vector<std::pair<std::string, std::string>>& components) {
  const std::string file = std::filesystem::path(exec).filename().string();
  if (file != "enact-sim") {
    return ComponentProblem{static_cast<std::size_t>(-1), file + " runs no components\n  fix: a stage of your own runs in enact-sim (after its model's step) or in "
                                                                 "enact-rt's tick: list it under one of those (component: [{name, plugin, library}])"};
  }
  for (std::size_t i = 0; i < components.size(); ++i) {
    const auto& [name, plugin] = components[i];
    const ComponentKind* kind = find_component_kind(plugin);
    if (!kind) {
      return ComponentProblem{i, "component '" + name + "': unknown plugin '" + plugin + "'\n  fix: give its plugin library (library: PATH in the launch file, --library=PATH to enact-sim)"};
    }
    if (kind->role != ComponentRole::stage) {
      return ComponentProblem{i, "component '" + name + "' is a " + kind->what + " (plugin " + plugin + "): enact-sim runs its own simulator, its drivers and observers are "
                                 "nodes of their own\n  fix: list only stages of a user's (plugin libraries) under enact-sim; a " + kind->what + " is a node, or a component of enact-rt"};
    }
  }
  return std::nullopt;
}

const ParamTable* node_table(const std::string& exec) {
  static const ParamTable sim = sim_node_table(), ffd = ffd_node_table(), tactile = tactile_node_table(), rt = rt_table();
  const std::string file = std::filesystem::path(exec).filename().string();
  if (file == "enact-sim") return &sim;
  if (file == "enact-ffd") return &ffd;
  if (file == "enact-tactile") return &tactile;
  if (file == "enact-rt") return &rt;
  if (file == "enact-logger") return &logger_component_table();
  if (file == "enact-foxglove") return &foxglove_component_table();
  return nullptr;
}

std::vector<std::string> check_params(const launch::LaunchDescription& graph) {
  std::vector<std::string> problems;
  for (const launch::NodeSpec& n : graph.nodes) {
    const ParamTable* table = node_table(n.path);
    if (!table) continue;
    std::vector<std::string> components;
    for (const launch::ComponentSpec& c : n.components) components.push_back(c.name);
    check_against(n, n.name, n.params, *table, components, problems);
    if (!n.components.empty()) check_components(n, problems);
    for (const launch::ComponentSpec& c : n.components) {
      if (const ParamTable* ct = component_table(c.plugin)) check_against(n, c.name, c.params, *ct, {}, problems);
    }
  }
  return problems;
}

std::vector<std::string> check_clock(const launch::LaunchDescription& graph) {
  std::vector<std::string> problems;
  if (graph.clock != rt::GraphClock::simulated) return problems;
  // a device other than the simulated ones, named by its `device` parameter
  auto refuse_real = [&](const launch::NodeSpec& n, const std::string& who, const std::vector<launch::Param>& params) {
    for (const launch::Param& p : params) {
      if (p.name != "device" || p.value == "simulated") continue;
      problems.push_back((p.source.empty() ? n.source : p.source) + ": node '" + n.name + "': " + who + " drives a real device (device=" + p.value +
                         "), and the graph's clock is simulated (" + graph.clock_source +
                         "): a person on a real device cannot be simulated\n  fix: run this graph in real time (clock: real, or leave out --clock "
                         "simulated), or give it device=simulated with a virtual subject (subject=FILE)");
    }
  };
  for (const launch::NodeSpec& n : graph.nodes) {
    const std::string exec = std::filesystem::path(n.path).filename().string();
    if (exec == "enact-ffd" || exec == "enact-tactile") refuse_real(n, exec.substr(6) + " driver", n.params);
    for (const launch::ComponentSpec& c : n.components) {
      if (c.plugin == "ffd" || c.plugin == "tactile") refuse_real(n, "component '" + c.name + "'", c.params);
    }
  }
  return problems;
}

std::vector<std::string> check_graph(const launch::LaunchDescription& graph) {
  std::vector<std::string> problems = check_clock(graph);
  if (!problems.empty()) return problems;
  problems = check_params(graph);
  return problems.empty() ? launch::check_nodes(graph) : problems;
}

}  // namespace enact::graph
