#include "core/replay/replay.h"

#include <cstdio>
#include <cstring>
#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "core/config/format.h"
#include "core/config/yaml.h"
#include "core/graph/messages.h"
#include "core/params/node_params.h"
#include "core/params/param_bus.h"
#include "core/params/params.h"
#include "core/record/logger.h"
#include "core/graph/temp_folder.h"
#include "core/graph/topics.h"
#include "core/sim/simulator.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/sim_keyframe.pb.h"
#include "msgs/tactile_frame.pb.h"

namespace enact::graph {
namespace {

struct State {
  std::uint64_t seq;
  std::int64_t stamp_ns;
  math::Vec3 position_m;
  bool cut;  // the force path was cut (the driver's watchdog, a device error): the simulator re-synchronises
  math::Vec3 velocity_m_per_s;
  std::uint32_t buttons;
  math::Vec3 force_n;  // acting on the hand as recorded
};

struct Force {
  math::Vec3 force_n;
  bool zero;
  std::uint64_t seq;  // the answer's own header.seq in the simulator's stream
};

// a live change as acknowledged: applied before the step on the state `state_seq`
struct Change {
  std::uint64_t state_seq;
  std::string publisher, param;
  sim::ParamValue value;
};

Change change_of(const msgs::ParamAck& a, std::string publisher) {
  Change c{a.state_seq(), std::move(publisher), a.name().substr(a.name().rfind('.') + 1), {}};
  if (a.value_case() == msgs::ParamAck::kNumber) c.value.number = a.number();
  if (a.value_case() == msgs::ParamAck::kText) c.value.text = a.text();
  if (c.param == "reset" || c.param == "reposition") c.value.flag = true;
  return c;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// every bit of a double in text (17 significant digits read back to the same value)
std::string exact(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// the simulator's parameters in the recording: the node (or container component) that
// published ffd/force; "" when the recording has no launch parameters
struct SimSource {
  std::string prefix;  // e.g. "sim." or "rt.sim."
  std::string rate_key;  // e.g. "sim.rate_hz" or "rt.rate_hz"
};

SimSource find_sim(const record::StringMap& params, const std::string& publisher) {
  for (const auto& [key, value] : params) {
    if (key.size() < 6 || key.compare(key.size() - 6, 6, ".scene") != 0) continue;
    const std::string prefix = key.substr(0, key.size() - 5);  // keeps the dot
    if (prefix == publisher + ".") return {prefix, prefix + "rate_hz"};
    if (prefix.rfind(publisher + ".", 0) == 0) return {prefix, publisher + ".rate_hz"};  // a component
  }
  return {};
}

// the recorded traffic: device states, the answers by state seq, the tactile frames, the
// simulator's acknowledged changes and keyframes
struct Traffic {
  std::vector<State> states;
  std::map<std::uint64_t, Force> forces;
  std::vector<std::vector<float>> frames;
  std::vector<std::uint64_t> frame_after;  // per frame: the state seq of the last answer recorded before it
  std::string sim_publisher;
  std::vector<Change> changes;
  std::vector<std::pair<std::string, msgs::SimKeyframe>> keyframes;  // with their publisher
};

Traffic read_traffic(record::Reader& r) {
  Traffic t;
  msgs::DeviceState state;
  msgs::ForceCommand command;
  msgs::TactileFrame frame;
  msgs::ParamAck ack;
  msgs::SimKeyframe keyframe;
  std::set<std::uint64_t> acked;  // request ids (a repeated request is acked again)
  r.for_each([&](const record::Message& m) {
    const auto pub = m.channel->metadata.find("publisher");
    const std::string publisher = pub == m.channel->metadata.end() ? "" : pub->second;
    auto parse = [&](google::protobuf::Message& msg) { return msg.ParseFromArray(m.data.data(), static_cast<int>(m.data.size())); };
    if (m.topic == kParamAck && parse(ack) && ack.applied() && ack.state_seq() != 0 && acked.insert(ack.request_id()).second) {
      t.changes.push_back(change_of(ack, publisher));
    } else if (m.topic == kDeviceState && parse(state)) {
      t.states.push_back({state.header().seq(), state.header().stamp_ns(), get(state.position()), force_path_cut(state.faults()), get(state.velocity()),
                          state.buttons(), get(state.force())});
    } else if (m.topic == kForceCommand && parse(command)) {
      t.forces[command.answered_seq()] = {get(command.force()), command.zero(), command.header().seq()};
      t.sim_publisher = publisher;
    } else if (m.topic == kTactileFrame && parse(frame)) {
      t.frames.emplace_back(frame.level().begin(), frame.level().end());
      t.frame_after.push_back(command.answered_seq());
    } else if (m.topic == kSimKeyframe && parse(keyframe)) {
      t.keyframes.emplace_back(publisher, keyframe);
    }
    return true;
  });
  if (t.states.empty()) {
    throw config::Error(r.path() + ": no ffd/state messages: nothing to replay\n  fix: record the device states (enact record --all)");
  }
  return t;
}

// the replay's start and the keyframe it starts from (nullptr: the first state)
std::pair<ReplayStart, const msgs::SimKeyframe*> find_start(const Traffic& t) {
  ReplayStart s;
  s.first_state_seq = t.states.front().seq;
  s.mid_run = s.first_state_seq != 1;
  if (!s.mid_run) return {s, nullptr};
  std::map<std::int64_t, std::size_t> by_stamp;
  for (std::size_t i = 0; i < t.states.size(); ++i) by_stamp.emplace(t.states[i].stamp_ns, i);
  for (const auto& [publisher, k] : t.keyframes) {
    const auto at = by_stamp.find(k.header().stamp_ns());
    if (publisher != t.sim_publisher || at == by_stamp.end()) continue;
    s.keyframe = true;
    s.keyframe_stamp_ns = k.header().stamp_ns();
    s.keyframe_state_seq = t.states[at->second].seq;
    s.keyframe_step = k.step();
    s.keyframe_time_s = static_cast<double>(k.header().stamp_ns() - k.origin_ns()) * 1e-9;
    s.skipped_s = static_cast<double>(k.header().stamp_ns() - t.states.front().stamp_ns) * 1e-9;
    return {s, &k};
  }
  return {s, nullptr};
}

}  // namespace

ReplayStart replay_start(record::Reader& r) { return find_start(read_traffic(r)).first; }

std::string describe(const ReplayStart& s) {
  if (!s.mid_run) return "";
  const std::string began = "started mid-run (its first ffd/state is seq " + std::to_string(s.first_state_seq) + ", not the graph's first)";
  if (!s.keyframe) {
    return began + " and holds no keyframe of the simulator after it: its state there is unknown, so a replay may differ\n"
                   "  fix: record sim/keyframe too (enact record --all), or from the graph's start";
  }
  char text[256];
  std::snprintf(text, sizeof text, ": replay begins at its first keyframe (sim/keyframe), after ffd/state seq %llu, simulator step %llu, %.3f s after it started (%.3f s into the recording)",
                static_cast<unsigned long long>(s.keyframe_state_seq), static_cast<unsigned long long>(s.keyframe_step), s.keyframe_time_s, s.skipped_s);
  return began + text;
}

namespace {

// the simulator's parameters as recorded (its files from the recording's attachments, into
// `files`), unless `options` overrides them; what ran goes to `out`
Params recorded_sim_params(record::Reader& r, const ResimOptions& options, const std::string& sim_publisher, TempFolder& files, ResimResult& out) {
  const record::StringMap recorded = r.metadata("enact.params");
  const SimSource src = find_sim(recorded, sim_publisher);
  Params p("resim");
  for (const auto& [key, value] : recorded) {
    if (!src.prefix.empty() && key.rfind(src.prefix, 0) == 0) p.set(key.substr(src.prefix.size()), value);
  }
  if (!src.prefix.empty() && recorded.count(src.rate_key)) p.set("rate_hz", recorded.at(src.rate_key));
  auto file_param = [&](const std::string& name, const std::string& given) {
    if (!given.empty()) return p.set(name, given);
    const auto data = r.attachment(src.prefix + name);
    const auto path = recorded.find(src.prefix + name);
    if (!data) return;
    // with the files it reads beside it (a scene's meshes and height maps)
    const graph::FilesBeside beside = graph::files_beside(r.attachments(), src.prefix + name, record::name_of, record::data_of);
    p.set(name, files.put(name, path == recorded.end() ? "" : path->second, *data, beside));
  };
  file_param("scene", options.scene);
  file_param("model", options.model);
  if (!p.has("scene")) {
    throw config::Error(r.path() + ": the recording holds no scene (it was not made from a graph started by `enact launch`)\n"
                                   "  fix: give the scene: enact resim FILE --scene SCENE.yaml");
  }
  const record::StringMap graph = r.metadata("enact.graph");
  if (graph.count("clock")) out.clock = graph.at("clock");
  out.scene = options.scene.empty() ? (recorded.count(src.prefix + "scene") ? recorded.at(src.prefix + "scene") : "") : options.scene;
  out.model = options.model.empty() ? (recorded.count(src.prefix + "model") ? recorded.at(src.prefix + "model") : "CM1") : options.model;
  return p;
}

// the stages of the loop whose simulator answered the states (node `sim_publisher`: a
// container, or enact-sim), in their order, with their parameters as recorded
std::vector<RecordedStage> recorded_stages(record::Reader& r, const std::string& sim_publisher) {
  const record::StringMap params = r.metadata("enact.params");
  std::vector<RecordedStage> out;
  for (const RecordedComponent& c : recorded_components(r.metadata("enact.components"))) {
    if (c.node != sim_publisher || c.library.empty()) continue;
    RecordedStage stage{c.name, c.plugin, c.library, {}};
    const std::string prefix = c.node + "." + c.name + ".";
    for (const auto& [key, value] : params) {
      if (key.rfind(prefix, 0) == 0) stage.params[key.substr(prefix.size())] = value;
    }
    out.push_back(std::move(stage));
  }
  return out;
}

// one replay in progress: the simulator stepped on the recorded states, compared as it goes
struct Replay {
  Replay(Traffic& t, sim::Simulator& s, sim::ParamPlanner& pl, ResimResult& o) : traffic(t), sim(s), planner(pl), out(o) {}
  Traffic& traffic;
  sim::Simulator& sim;  // its clock starts at the first state's stamp, or the keyframe's origin
  sim::ParamPlanner& planner;
  ResimResult& out;
  std::size_t first = 0, next_change = 0, next_frame = 0;
  msgs::TactileFrame frame;
  StageStep stages;  // the recorded loop's stages, if it had any
  sim::StepOutput staged;  // the model's output as they left it

  void diverge(std::uint64_t seq, const char* topic, std::string field, std::string rec, std::string rep) {
    if (!out.divergence) out.divergence = Divergence{out.steps, seq, topic, std::move(field), std::move(rec), std::move(rep)};
  }

  // the simulator as it was after the keyframe's state, the states from the next one, the
  // simulator's clock from its first state
  void from_keyframe(const record::Reader& r, const msgs::SimKeyframe& keyframe, const ReplayStart& start) {
    sim::Keyframe k;
    sim.save(k);
    if (!sim::unpack(keyframe.memory(), k)) {
      throw config::Error(r.path() + ": its keyframe (sim/keyframe) was made by another build of enact or for another scene\n"
                                     "  fix: replay it with the enact that recorded it");
    }
    sim.restore(k);
    planner.follow(sim);
    const std::vector<State>& states = traffic.states;
    while (first < states.size() && states[first].stamp_ns != start.keyframe_stamp_ns) ++first;
    ++first;
    std::erase_if(traffic.changes, [&](const Change& c) { return c.state_seq <= start.keyframe_state_seq; });
    while (next_frame < traffic.frames.size() && traffic.frame_after[next_frame] <= start.keyframe_state_seq) ++next_frame;
  }

  // the live changes the simulator applied before the step that first used them
  void apply_changes(const State& s) {
    for (; next_change < traffic.changes.size() && traffic.changes[next_change].state_seq <= s.seq; ++next_change) {
      const Change& c = traffic.changes[next_change];
      const sim::ParamPlan plan = planner.plan(c.param, c.value, next_change + 1);
      if (plan.accepted) sim.apply(plan.change, 0);
      else diverge(s.seq, kParamAck, c.param, "applied", "refused: " + plan.reason);
    }
  }

  void compare_force(const State& s, const Force& recorded, const math::Vec3& replayed) {
    ++out.forces_compared;
    const char* axis[3] = {"force.x", "force.y", "force.z"};
    const double rec[3] = {recorded.force_n.x, recorded.force_n.y, recorded.force_n.z}, rep[3] = {replayed.x, replayed.y, replayed.z};
    for (int k = 0; k < 3; ++k) {
      if (!same_bits(rec[k], rep[k])) diverge(s.seq, kForceCommand, axis[k], exact(rec[k]), exact(rep[k]));
    }
  }

  void compare_frame(const State& s, std::uint32_t levels) {
    const physics::Proxy& body = sim.model().proxies[0];
    fill(frame, body.rows, body.cols, levels);
    const std::vector<float>& rec = traffic.frames[next_frame];
    for (int k = 0; k < frame.level_size(); ++k) {
      const float recorded_level = k < static_cast<int>(rec.size()) ? rec[k] : -1.0f;
      if (recorded_level != frame.level(k)) {
        diverge(s.seq, kTactileFrame, "level." + std::to_string(k) + " of frame " + std::to_string(next_frame), config::number(recorded_level),
                config::number(frame.level(k)));
      }
    }
    ++next_frame;
    ++out.frames_compared;
  }

  // one recorded state, as the recorded simulator took it
  void step(const State& s) {
    apply_changes(s);
    const auto f = traffic.forces.find(s.seq);
    if (f == traffic.forces.end()) {
      // the answers either side of this state: consecutive in the simulator's stream, so it
      // answered nothing in between: it never received this state
      const auto next = traffic.forces.upper_bound(s.seq);
      if (next != traffic.forces.end() && next != traffic.forces.begin() && std::prev(next)->second.seq + 1 == next->second.seq) {
        ++out.forces_missing;
        ++out.states_never_received;
        return;
      }
    }
    const sim::StepOutput* o = &sim.step_sample(s.stamp_ns, s.position_m, s.cut);
    const std::int64_t t_ns = s.stamp_ns - sim.origin_ns();
    if (stages) {
      staged = *o;
      stages(s.stamp_ns, t_ns, devices::ForceSample{s.stamp_ns, s.position_m, s.velocity_m_per_s, s.buttons, 0, s.force_n}, staged);
      o = &staged;
    }
    if (f == traffic.forces.end()) ++out.forces_missing;
    else compare_force(s, f->second, o->force_n);
    if (o->frame_due && next_frame < traffic.frames.size()) compare_frame(s, o->frame);
    ++out.steps;
  }
};

}  // namespace

std::string recorded_sim_param(const std::string& recording, const std::string& name, TempFolder& files) {
  record::Reader r(recording);
  // the simulator: the publisher of the answers, else the one node with a scene parameter
  std::string publisher;
  r.for_each([&](const record::Message& m) {
    if (m.topic != kForceCommand) return true;
    const auto pub = m.channel->metadata.find("publisher");
    if (pub != m.channel->metadata.end()) publisher = pub->second;
    return false;
  });
  if (publisher.empty()) {
    for (const auto& [key, value] : r.metadata("enact.params")) {
      if (key.size() > 6 && key.compare(key.size() - 6, 6, ".scene") == 0) publisher = key.substr(0, key.find('.'));
    }
  }
  ResimResult out;
  const Params p = recorded_sim_params(r, {}, publisher, files, out);
  p.declare(*node_table("enact-sim"));
  if (!p.has(name)) {
    throw config::Error(recording + ": the recording holds no simulator parameter '" + name + "'\n  fix: give it yourself (--arg), or check the name: enact info " + recording);
  }
  return p.text(name);
}

ResimResult resim(record::Reader& r, const ResimOptions& options) {
  Traffic traffic = read_traffic(r);
  // another scene or model replays from the first state, as a fresh simulator would
  auto [start, keyframe] = find_start(traffic);
  if (!options.scene.empty() || !options.model.empty()) keyframe = nullptr;

  // the simulator as recorded, with the recorded files, unless overridden
  ResimResult out;
  TempFolder files;
  Params p = recorded_sim_params(r, options, traffic.sim_publisher, files, out);
  sim::Simulator sim;
  p.declare(*node_table("enact-sim"));
  sim.configure(sim_params(p));
  sim.activate(0);  // as enact-sim and enact-rt: step_sample on each recorded state
  out.rate_hz = sim.model().rate_hz;
  out.start = start;
  sim::ParamPlanner planner(sim);
  Replay replay(traffic, sim, planner, out);
  // the stages a user wrote for the recorded loop, made again, each tick after the model
  out.stages = recorded_stages(r, traffic.sim_publisher);
  if (!out.stages.empty()) {
    if (!options.stages) {
      throw config::Error(r.path() + ": its loop stepped " + std::to_string(out.stages.size()) + " stage(s) a user wrote (the first: '" + out.stages[0].name +
                          "', plugin " + out.stages[0].plugin + " from " + out.stages[0].library + "), which a replay steps too\n"
                          "  fix: replay it with enact resim or enact metrics, which load them");
    }
    replay.stages = options.stages(out.stages);
  }
  if (keyframe) replay.from_keyframe(r, *keyframe, start);
  out.start.keyframe = keyframe != nullptr;
  out.first_state_seq = replay.first < traffic.states.size() ? traffic.states[replay.first].seq : 0;

  // the simulator's live changes, in the order it applied them, each before the step that
  // first used it
  std::erase_if(traffic.changes, [&](const Change& c) { return c.publisher != traffic.sim_publisher; });
  std::stable_sort(traffic.changes.begin(), traffic.changes.end(), [](const Change& a, const Change& b) { return a.state_seq < b.state_seq; });
  out.changes = traffic.changes.size();

  // step on every recorded state, as the recorded simulator did; compare as we go
  for (std::size_t i = replay.first; i < traffic.states.size(); ++i) replay.step(traffic.states[i]);
  out.metrics = sim.metrics();
  out.task = sim.has_task();
  sim.deactivate();
  return out;
}

}  // namespace enact::graph
