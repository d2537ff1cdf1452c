#include "core/sim/params.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>

#include "core/config/format.h"
#include "core/config/number.h"
#include "core/config/yaml.h"
#include "core/devices/device_profile.h"
#include "core/physics/stability.h"
#include "core/sim/simulator.h"

namespace enact::sim {
namespace {

// a number with `digits` significant digits, for messages
std::string num(double v, int digits = 4) {
  std::ostringstream out;
  out << std::setprecision(digits) << v;
  return out.str();
}

ParamPlan refuse(std::string reason) { return {false, {}, std::move(reason)}; }

ParamPlan accept(ParamKind kind, std::uint64_t request_id, double value = 0.0) {
  ParamPlan p;
  p.accepted = true;
  p.change.request_id = request_id;
  p.change.kind = kind;
  p.change.value = value;
  return p;
}

// a number given as a number, or as text that is one
std::optional<double> number_of(const ParamValue& v) {
  if (v.number) return v.number;
  return v.text ? config::parse_number(*v.text) : std::nullopt;
}

// the first contact pair of the body (-1 when it has none)
int first_body_contact(const physics::Model& m) {
  for (std::size_t i = 0; i < m.contacts.size(); ++i) {
    if (is_body_point(m, m.contacts[i].point)) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace

bool is_body_point(const physics::Model& m, int point) {
  const physics::Point& p = m.points[point];
  return p.proxy == 0;
}

const std::vector<std::string>& param_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n{"model"};
    for (const LiveNumber& number : live_numbers()) n.emplace_back(number.name);
    for (const char* command : {"reset", "reposition", "trial"}) n.emplace_back(command);
    return n;
  }();
  return names;
}

void set_body_contacts(physics::Model& model, std::optional<double> stiffness, std::optional<double> damping) {
  for (physics::ContactPair& c : model.contacts) {
    if (!is_body_point(model, c.point)) continue;
    if (stiffness) c.stiffness_n_per_m = *stiffness;
    if (damping) c.damping_n_s_per_m = *damping;
  }
}

namespace {

// the body's first contact pair's (0 without one)
const physics::ContactPair* body_contact(const physics::Model& m) {
  const int pair = first_body_contact(m);
  return pair < 0 ? nullptr : &m.contacts[pair];
}

}  // namespace

const std::vector<LiveNumber>& live_numbers() {
  using M = physics::Model;
  using CM = haptics::ComputerModel;
  constexpr double kNone = std::numeric_limits<double>::infinity();
  static const std::vector<LiveNumber> rows{
      {.name = "threshold_m", .min = 0, .max = haptics::kMaxThreshold_m, .doc = "penetration before force is felt (the computer model's)",
       .example = "0.003", .law = LawChange::if_new, .at_start = nullptr,
       .get = [](const M&, const CM& cm, const SimParams&) { return cm.threshold_m; },
       .set = [](LiveTarget& t, double v) {
         t.cm.threshold_m = v;
         haptics::apply(t.cm, t.model);
       }},
      {.name = "stiffness_n_per_m", .min = 0, .max = kNone, .doc = "contact stiffness of the body (checked against the stability analysis)",
       .example = "2000", .law = LawChange::always, .at_start = nullptr,
       .get = [](const M& m, const CM&, const SimParams&) { return body_contact(m) ? body_contact(m)->stiffness_n_per_m : 0.0; },
       .set = [](LiveTarget& t, double v) { set_body_contacts(t.model, v, std::nullopt); },
       .check = [](const ParamPlanner& p, double v) { return p.contact_refusal(true, v); }},
      {.name = "damping_n_s_per_m", .min = 0, .max = kNone, .doc = "contact damping of the body (checked against the stability analysis)",
       .example = "0.5", .law = LawChange::always, .at_start = nullptr,
       .get = [](const M& m, const CM&, const SimParams&) { return body_contact(m) ? body_contact(m)->damping_n_s_per_m : 0.0; },
       .set = [](LiveTarget& t, double v) { set_body_contacts(t.model, std::nullopt, v); },
       .check = [](const ParamPlanner& p, double v) { return p.contact_refusal(false, v); }},
      {.name = "change_ramp_s", .min = 0, .max = 10, .doc = "a live change's force blends from the old to the new law over this time",
       .example = "0.05", .law = LawChange::none, .at_start = &SimParams::change_ramp_s,
       .get = [](const M&, const CM&, const SimParams& p) { return p.change_ramp_s; },
       .set = [](LiveTarget& t, double v) { t.params.change_ramp_s = v; }},
      {.name = "friction_dynamic", .min = 0, .max = kNone, .doc = "the coefficient the body's contacts with friction slide with (their friction.dynamic; at most friction.static)",
       .example = "0.3", .law = LawChange::always, .at_start = nullptr,
       .get = [](const M& m, const CM&, const SimParams&) {
         for (const physics::ContactPair& c : m.contacts) {
           if (is_body_point(m, c.point) && c.friction.enabled()) return c.friction.dynamic_coeff;
         }
         return 0.0;
       },
       .set = [](LiveTarget& t, double v) {
         for (physics::ContactPair& c : t.model.contacts) {
           if (is_body_point(t.model, c.point) && c.friction.enabled()) c.friction.dynamic_coeff = std::min(v, c.friction.static_coeff);
         }
       },
       .check = [](const ParamPlanner& p, double v) -> std::string {
         for (const physics::ContactPair& c : p.model().contacts) {
           if (!is_body_point(p.model(), c.point) || !c.friction.enabled()) continue;
           if (v <= c.friction.static_coeff) return {};
           return "friction_dynamic = " + config::number(v) + " is above friction.static " + config::number(c.friction.static_coeff) + "\n  fix: at most " + config::number(c.friction.static_coeff);
         }
         return "friction_dynamic: no contact of the scene's body has friction\n  fix: give its contacts friction: {static: 0.6, dynamic: 0.4, stiffness_n_per_m: 2000}";
       }},
  };
  return rows;
}

const LiveNumber* find_live_number(const std::string& name) {
  for (const LiveNumber& n : live_numbers()) {
    if (name == n.name) return &n;
  }
  return nullptr;
}

namespace {

// a deformable body's masses carry its contacts: at the new value they must keep the
// integrator's bound ("" when they do, or the body is rigid)
std::string deformable_refusal(physics::Model model, std::optional<double> stiffness, std::optional<double> damping) {
  if (model.proxies.empty() || !model.proxies[0].deformable.enabled()) return {};
  set_body_contacts(model, stiffness, damping);
  const physics::StabilityReport report = physics::analyze_stability(model);
  return report.stable() ? std::string{} : physics::instability_message(model, report);
}

}  // namespace

PassivityDemand body_passivity_demand(const physics::Model& loaded) {
  physics::Model model = loaded;
  // the worst computer model: every body point feeds the device
  for (physics::Point& p : model.points) {
    if (p.proxy == 0) p.feeds_device = true;
  }
  // any device damping: only the demand K T/2 + B is read
  auto demand = [&](double stiffness, double damping) {
    set_body_contacts(model, stiffness, damping);
    const physics::StabilityReport report = physics::analyze_stability(model, 0.0);
    return report.devices.empty() ? 0.0 : report.devices[0].required_n_s_per_m;
  };
  PassivityDemand d;
  d.at_zero = demand(0.0, 0.0);
  d.per_n_per_m = demand(1.0, 0.0) - d.at_zero;
  d.per_n_s_per_m = demand(0.0, 1.0) - d.at_zero;
  return d;
}

ModelChange to_change(const haptics::ComputerModel& cm) {
  ModelChange c;
  c.force_grid_mask = cm.force_grid_mask;
  c.force_center = cm.force_center;
  c.pin_mask = cm.pin_mask;
  c.pins = cm.pins;
  c.threshold_m = cm.threshold_m;
  const std::size_t n = std::min(cm.name.size(), kMaxModelName);
  std::memcpy(c.name, cm.name.data(), n);
  c.name[n] = '\0';
  return c;
}

void assign(haptics::ComputerModel& cm, const ModelChange& c) {
  cm.force_grid_mask = c.force_grid_mask;
  cm.force_center = c.force_center;
  cm.pin_mask = c.pin_mask;
  cm.pins = c.pins;
  cm.threshold_m = c.threshold_m;
  cm.name.assign(c.name);
}

namespace {
double envelope(const physics::Model& model, const PassivityDemand& demand) {
  const auto profile = devices::find_device_profile(model.device_profile);
  const int pair = first_body_contact(model);
  const double loaded = pair < 0 ? 0.0 : demand.at(model.contacts[pair].stiffness_n_per_m, model.contacts[pair].damping_n_s_per_m);
  return std::max(profile ? profile->damping_n_s_per_m : 0.0, loaded);
}
}  // namespace

double passivity_envelope(const physics::Model& model) { return envelope(model, body_passivity_demand(model)); }

ParamPlanner::ParamPlanner(const Simulator& simulator)
    : model_(simulator.model()),
      cm_(simulator.computer_model()),
      params_(simulator.params()),
      grid_masses_(simulator.grid_masses()),
      demand_(body_passivity_demand(model_)),
      envelope_(envelope(model_, demand_)) {
  if (const auto profile = devices::find_device_profile(model_.device_profile)) device_damping_ = profile->damping_n_s_per_m;
}

void ParamPlanner::follow(const Simulator& simulator) {
  model_ = simulator.model();
  cm_ = simulator.computer_model();
  params_ = simulator.params();
}

double ParamPlanner::stiffness_n_per_m() const {
  const int pair = first_body_contact(model_);
  return pair < 0 ? 0.0 : model_.contacts[pair].stiffness_n_per_m;
}

double ParamPlanner::damping_n_s_per_m() const {
  const int pair = first_body_contact(model_);
  return pair < 0 ? 0.0 : model_.contacts[pair].damping_n_s_per_m;
}

std::string ParamPlanner::contact_refusal(bool stiffness, double value) const {
  const char* name = stiffness ? "stiffness_n_per_m" : "damping_n_s_per_m";
  const char* unit = stiffness ? "N/m" : "N s/m";
  if (first_body_contact(model_) < 0) return std::string(name) + ": the scene's body has no contacts\n  fix: add a contacts: entry for the body";
  // the passivity demand is linear in the changed parameter, the other one held
  const double k = stiffness_n_per_m(), z = damping_n_s_per_m();
  auto demand = [&](double v) { return demand_.at(stiffness ? v : k, stiffness ? z : v); };
  const double asked = demand(value);
  if (asked > envelope_ * (1.0 + 1e-12)) {
    const double at0 = demand(0.0), slope = demand(1.0) - at0;
    const double largest = slope > 0.0 ? std::max(0.0, (envelope_ - at0) / slope) : 0.0;
    const std::string device = model_.device_profile.empty() ? "a device without a profile (b = 0)" : model_.device_profile;
    return std::string(name) + " = " + num(value, 6) + " " + unit + ": the loop would not stay stable on " + device + " at " + num(model_.rate_hz, 6) +
           " Hz: the passivity bound (Colgate & Schenkel) needs K T/2 + B = " + num(asked) + " N s/m with every body point in contact, past " +
           num(envelope_) + " N s/m (the device damping b = " + num(device_damping_) + " N s/m, or the scene as loaded if larger)\n  fix: at most " +
           num(largest, 6) + " " + unit;
  }
  const std::optional<double> new_k = stiffness ? std::optional(value) : std::nullopt, new_z = stiffness ? std::nullopt : std::optional(value);
  const std::string unstable = deformable_refusal(model_, new_k, new_z);
  if (!unstable.empty()) return std::string(name) + " = " + num(value, 6) + " " + unit + ": the deformable body would not stay stable: " + unstable;
  return {};
}

double ParamPlanner::value(const LiveNumber& number) const { return number.get(model_, cm_, params_); }

ParamPlan ParamPlanner::plan(const std::string& name, const ParamValue& value, std::uint64_t request_id) {
  if (name == "model") {
    if (!value.text || value.text->empty()) return refuse("model needs a text value\n  fix: a preset (CM0, CM1, CM2, CM3, P, T, PT) or a YAML file");
    haptics::ComputerModel cm;
    try {
      cm = haptics::resolve_computer_model(*value.text, grid_masses_);
    } catch (const config::Error& e) {
      return refuse(e.what());
    }
    if (cm.name.size() > kMaxModelName) return refuse("model name '" + cm.name + "' is longer than " + std::to_string(kMaxModelName) + " characters\n  fix: give it a shorter name:");
    cm_ = cm;
    ParamPlan p = accept(ParamKind::model, request_id);
    p.change.model = to_change(cm);
    return p;
  }
  if (const LiveNumber* number = find_live_number(name)) {
    const std::optional<double> v = number_of(value);
    const std::string unit = config::unit_of(number->name).empty() ? "" : " " + config::unit_of(number->name);
    if (!v || !std::isfinite(*v) || *v < number->min || *v > number->max) {
      const std::string range = std::isfinite(number->max) ? "from " + config::number(number->min) + " to " + config::number(number->max) + unit
                                                           : ">= " + config::number(number->min) + unit;
      return refuse(name + " must be a number " + range + "\n  fix: e.g. " + number->example + unit);
    }
    // the value in force changes nothing (a dump of the values in force loads back whole)
    if (number->check && *v != this->value(*number)) {
      if (std::string problem = number->check(*this, *v); !problem.empty()) return refuse(std::move(problem));
    }
    LiveTarget target = mirror();
    number->set(target, *v);
    ParamPlan p = accept(ParamKind::number, request_id, *v);
    p.change.number = static_cast<std::uint8_t>(number - live_numbers().data());
    return p;
  }
  if (name == "reset") return accept(ParamKind::reset, request_id);
  if (name == "reposition") return accept(ParamKind::reposition, request_id);
  if (name == "trial") {
    const std::string t = value.text.value_or("");
    if (t == "start" || value.flag == true) return accept(ParamKind::trial_start, request_id);
    if (t == "stop" || value.flag == false) return accept(ParamKind::trial_stop, request_id);
    return refuse("trial needs start or stop\n  fix: sim.trial start, or sim.trial stop");
  }
  std::string names;
  for (const std::string& n : param_names()) names += (names.empty() ? "" : ", ") + n;
  return refuse("unknown parameter '" + name + "'\n  fix: use one of " + names);
}

}  // namespace enact::sim
