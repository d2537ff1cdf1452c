#include "core/graph/replay.h"

#include <cstdio>
#include <cstring>
#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "core/config/format.h"
#include "core/config/yaml.h"
#include "core/graph/components.h"
#include "core/graph/messages.h"
#include "core/graph/node_params.h"
#include "core/graph/param_bus.h"
#include "core/graph/params.h"
#include "core/graph/temp_folder.h"
#include "core/graph/topics.h"
#include "core/sim/reengage.h"
#include "core/sim/simulator.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/tactile_frame.pb.h"

namespace enact::graph {
namespace {

struct State {
  std::uint64_t seq;
  std::int64_t stamp_ns;
  math::Vec3 position_m;
  bool cut;  // the force path was cut (the driver's watchdog, a device error): the simulator re-synchronises
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

}  // namespace

ResimResult resim(record::Reader& r, const ResimOptions& options) {
  // the recorded traffic: device states, the answers by state seq, the tactile frames
  std::vector<State> states;
  std::map<std::uint64_t, Force> forces;
  std::vector<std::vector<float>> frames;
  std::string sim_publisher;
  msgs::DeviceState state;
  msgs::ForceCommand command;
  msgs::TactileFrame frame;
  msgs::ParamAck ack;
  std::vector<Change> changes;
  std::set<std::uint64_t> acked;  // request ids (a repeated request is acked again)
  r.for_each([&](const record::Message& m) {
    const auto pub = m.channel->metadata.find("publisher");
    if (m.topic == kParamAck && ack.ParseFromArray(m.data.data(), static_cast<int>(m.data.size())) && ack.applied() && ack.state_seq() != 0 &&
        acked.insert(ack.request_id()).second) {
      changes.push_back(change_of(ack, pub == m.channel->metadata.end() ? "" : pub->second));
    }
    if (m.topic == kDeviceState && state.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      states.push_back({state.header().seq(), state.header().stamp_ns(), get(state.position()),
                        force_path_cut(state.faults())});
    } else if (m.topic == kForceCommand && command.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      forces[command.answered_seq()] = {get(command.force()), command.zero(), command.header().seq()};
      if (pub != m.channel->metadata.end()) sim_publisher = pub->second;
    } else if (m.topic == kTactileFrame && frame.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      frames.emplace_back(frame.level().begin(), frame.level().end());
    }
    return true;
  });
  if (states.empty()) {
    throw config::Error(r.path() + ": no ffd/state messages: nothing to replay\n  fix: record the device states (enact record --all)");
  }

  // the simulator as recorded, with the recorded files, unless overridden
  const record::StringMap recorded = r.metadata("enact.params");
  const SimSource src = find_sim(recorded, sim_publisher);
  Params p("resim");
  for (const auto& [key, value] : recorded) {
    if (!src.prefix.empty() && key.rfind(src.prefix, 0) == 0) p.set(key.substr(src.prefix.size()), value);
  }
  if (!src.prefix.empty() && recorded.count(src.rate_key)) p.set("rate_hz", recorded.at(src.rate_key));
  TempFolder files;
  auto file_param = [&](const std::string& name, const std::string& given) {
    if (!given.empty()) return p.set(name, given);
    const auto data = r.attachment(src.prefix + name);
    const auto path = recorded.find(src.prefix + name);
    if (data) p.set(name, files.put(name, path == recorded.end() ? "" : path->second, *data));
  };
  file_param("scene", options.scene);
  file_param("model", options.model);
  if (!p.has("scene")) {
    throw config::Error(r.path() + ": the recording holds no scene (it was not made from a graph started by `enact launch`)\n"
                                   "  fix: give the scene: enact resim FILE --scene SCENE.yaml");
  }
  ResimResult out;
  const record::StringMap graph = r.metadata("enact.graph");
  if (graph.count("clock")) out.clock = graph.at("clock");
  out.scene = options.scene.empty() ? (recorded.count(src.prefix + "scene") ? recorded.at(src.prefix + "scene") : "") : options.scene;
  out.model = options.model.empty() ? (recorded.count(src.prefix + "model") ? recorded.at(src.prefix + "model") : "CM1") : options.model;
  sim::Simulator sim;
  p.declare(*node_table("enact-sim"));
  sim.configure(sim_params(p));
  sim.activate(0);
  // as enact-sim and enact-rt: the body re-synchronises with the device at the first step
  // and whenever the force path was cut
  sim::Reengagement reengage(p.number("reengage_s"));
  reengage.interrupt();
  out.rate_hz = sim.model().rate_hz;
  out.first_state_seq = states.front().seq;

  // the simulator's live changes, in the order it applied them, each before the step that
  // first used it
  std::erase_if(changes, [&](const Change& c) { return c.publisher != sim_publisher; });
  std::stable_sort(changes.begin(), changes.end(), [](const Change& a, const Change& b) { return a.state_seq < b.state_seq; });
  sim::ParamPlanner planner(sim);
  std::size_t next_change = 0;
  out.changes = changes.size();

  // step on every recorded state, as the recorded simulator did; compare as we go
  const physics::Proxy& body = sim.model().proxies[0];
  const std::int64_t t0 = states.front().stamp_ns;
  std::size_t next_frame = 0;
  auto diverge = [&](std::uint64_t step, std::uint64_t seq, const char* topic, std::string field, std::string rec, std::string rep) {
    if (!out.divergence) out.divergence = Divergence{step, seq, topic, std::move(field), std::move(rec), std::move(rep)};
  };
  for (const State& s : states) {
    for (; next_change < changes.size() && changes[next_change].state_seq <= s.seq; ++next_change) {
      const Change& c = changes[next_change];
      const sim::ParamPlan plan = planner.plan(c.param, c.value, next_change + 1);
      if (plan.accepted) sim.apply(plan.change, 0);
      else diverge(out.steps, s.seq, kParamAck, c.param, "applied", "refused: " + plan.reason);
    }
    const auto f = forces.find(s.seq);
    if (f == forces.end()) {
      // the answers either side of this state: consecutive in the simulator's stream, so it
      // answered nothing in between: it never received this state
      const auto next = forces.upper_bound(s.seq);
      if (next != forces.end() && next != forces.begin() && std::prev(next)->second.seq + 1 == next->second.seq) {
        ++out.forces_missing;
        ++out.states_never_received;
        continue;
      }
    }
    if (s.cut) reengage.interrupt();
    const std::int64_t t_ns = s.stamp_ns - t0;
    const sim::StepOutput& o = sim.step(t_ns, reengage.position(sim, t_ns, s.position_m));
    if (f == forces.end()) {
      ++out.forces_missing;
    } else {
      ++out.forces_compared;
      const math::Vec3& a = f->second.force_n;
      const char* axis[3] = {"force.x", "force.y", "force.z"};
      const double rec[3] = {a.x, a.y, a.z}, rep[3] = {o.force_n.x, o.force_n.y, o.force_n.z};
      for (int k = 0; k < 3; ++k) {
        if (!same_bits(rec[k], rep[k])) diverge(out.steps, s.seq, kForceCommand, axis[k], exact(rec[k]), exact(rep[k]));
      }
    }
    if (o.frame_due && next_frame < frames.size()) {
      fill(frame, body.rows, body.cols, o.frame);
      const std::vector<float>& rec = frames[next_frame];
      for (int k = 0; k < frame.level_size(); ++k) {
        const float recorded_level = k < static_cast<int>(rec.size()) ? rec[k] : -1.0f;
        if (recorded_level != frame.level(k)) {
          diverge(out.steps, s.seq, kTactileFrame, "level." + std::to_string(k) + " of frame " + std::to_string(next_frame),
                  config::number(recorded_level), config::number(frame.level(k)));
        }
      }
      ++next_frame;
      ++out.frames_compared;
    }
    ++out.steps;
  }
  out.metrics = sim.metrics();
  sim.deactivate();
  return out;
}

}  // namespace enact::graph
