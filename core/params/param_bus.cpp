#include "core/params/param_bus.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "core/config/format.h"
#include "core/config/number.h"
#include "core/config/suggest.h"
#include "core/graph/graph_dir.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"

namespace enact::graph {
namespace {

// answers kept for requests sent again
constexpr std::size_t kAnswersKept = 64;
// model names kept with the time they took effect
constexpr std::size_t kNamesKept = 16;

}  // namespace

sim::ParamValue value_of(const msgs::ParamUpdate& m) {
  sim::ParamValue v;
  switch (m.value_case()) {
    case msgs::ParamUpdate::kNumber: v.number = m.number(); break;
    case msgs::ParamUpdate::kText: v.text = m.text(); break;
    case msgs::ParamUpdate::kFlag: v.flag = m.flag(); break;
    case msgs::ParamUpdate::VALUE_NOT_SET: break;
  }
  return v;
}

void set_value(msgs::ParamUpdate& m, const std::string& value) {
  if (const auto number = config::parse_number(value)) m.set_number(*number);
  else if (value == "true" || value == "false") m.set_flag(value == "true");
  else m.set_text(value);
}

void set_value(msgs::ParamUpdate& m, const sim::ParamValue& value) {
  if (value.number) m.set_number(*value.number);
  else if (value.text) m.set_text(*value.text);
  else if (value.flag) m.set_flag(*value.flag);
}

ParamPort::ParamPort(const sim::Simulator& simulator, std::string prefix, bus::BytePublisher& out, bus::Publisher<msgs::TaskEvent>& events,
                     ParamBoard* board)
    : planner_(simulator),
      prefix_(std::move(prefix) + "."),
      in_(in_bytes_, kParamSet),
      acks_(out, kParamAck),
      events_(events),
      names_{{INT64_MIN, simulator.computer_model().name}},
      board_(board) {
  in_bytes_.connect(node_endpoint(kInboundNode));
  // the live-only parameters as the scene and model set them
  if (board_) {
    for (const sim::LiveNumber& n : sim::live_numbers()) board_->set(prefix_ + n.name, config::number(planner_.value(n)));
  }
  planning_ = std::thread([this] { plan_all(); });
}

ParamPort::~ParamPort() {
  stopping_.store(true);
  wake_.release();
  planning_.join();
}

void ParamPort::plan_all() {
  PlanRequest r;
  Plan p;
  while (!stopping_.load()) {
    (void)wake_.try_acquire_for(std::chrono::milliseconds(100));
    while (to_plan_.try_pop(r)) {
      sim::ParamValue value;
      if (r.value_case == msgs::ParamUpdate::kNumber) value.number = r.number;
      if (r.value_case == msgs::ParamUpdate::kFlag) value.flag = r.flag;
      if (r.value_case == msgs::ParamUpdate::kText) value.text = r.text;
      const sim::ParamPlan plan = planner_.plan(r.name, value, r.id);
      p = Plan{.id = r.id, .accepted = plan.accepted, .change = plan.change, .threshold_m = planner_.computer_model().threshold_m};
      std::snprintf(p.reason, sizeof p.reason, "%s", plan.reason.c_str());
      std::snprintf(p.model, sizeof p.model, "%s", planner_.computer_model().name.c_str());
      // never full: no more requests are in flight than it holds
      planned_.try_push(p);
    }
  }
}

void ParamPort::submit(std::uint64_t id) {
  const std::string name = request_.name().substr(prefix_.size());
  PlanRequest r{.id = id, .value_case = request_.value_case(), .number = request_.number(), .flag = request_.flag()};
  if (name.size() >= sizeof r.name) return refuse(id, request_.name(), "unknown parameter '" + name + "'\n  fix: see enact param list");
  if (request_.text().size() > kMaxText) return refuse(id, request_.name(), "a text of at most " + std::to_string(kMaxText) + " characters");
  std::snprintf(r.name, sizeof r.name, "%s", name.c_str());
  std::snprintf(r.text, sizeof r.text, "%s", request_.text().c_str());
  in_flight_[id].request = request_;
  to_plan_.try_push(r);  // never full: no more requests are in flight than it holds
  wake_.release();
}

std::optional<sim::ParamChange> ParamPort::next() {
  while (in_flight_.size() < sim::kMaxParamsInFlight && in_.receive(request_, 0)) {
    // another node's parameter
    if (!request_.name().starts_with(prefix_)) continue;
    // a request sent again: answer it again once known, never apply it twice
    const std::uint64_t id = request_.request_id();
    if (in_flight_.contains(id)) continue;
    bool repeated = false;
    for (msgs::ParamAck& a : answered_) {
      if (a.request_id() != id) continue;
      acks_.publish(a);
      repeated = true;
    }
    if (!repeated) submit(id);
  }
  Plan plan;
  while (planned_.try_pop(plan)) {
    if (auto change = take(plan)) return change;
  }
  return std::nullopt;
}

std::optional<sim::ParamChange> ParamPort::take(const Plan& plan) {
  const auto it = in_flight_.find(plan.id);
  if (it == in_flight_.end()) return std::nullopt;
  InFlight& f = it->second;
  if (!plan.accepted) {
    const std::string name = f.request.name();
    in_flight_.erase(it);
    refuse(plan.id, name, plan.reason);
    return std::nullopt;
  }
  // the ack names the value applied
  f.model = plan.change.kind == sim::ParamKind::model ? plan.model : "";
  f.threshold_m = plan.threshold_m;
  f.ack.set_request_id(plan.id);
  f.ack.set_applied(true);
  f.ack.set_name(f.request.name());
  switch (plan.change.kind) {
    case sim::ParamKind::number: f.ack.set_number(plan.change.value); break;
    case sim::ParamKind::model: f.ack.set_text(f.request.text()); break;
    case sim::ParamKind::trial_start: f.ack.set_text("start"); break;
    case sim::ParamKind::trial_stop: f.ack.set_text("stop"); break;
    case sim::ParamKind::reset:
    case sim::ParamKind::reposition: break;
  }
  return plan.change;
}

void ParamPort::applied(const sim::ParamApplied& a) {
  const auto it = in_flight_.find(a.request_id);
  if (it == in_flight_.end()) return;
  InFlight& f = it->second;
  if (a.kind == sim::ParamKind::model) names_.emplace_back(a.time_ns, f.model);
  if (names_.size() > kNamesKept) names_.pop_front();
  f.step = a.step;
  // the values in force, for observers
  if (board_ && f.ack.value_case() == msgs::ParamAck::kNumber) board_->set(f.ack.name(), config::number(f.ack.number()));
  if (board_ && a.kind == sim::ParamKind::model) {
    board_->set(f.ack.name(), f.ack.text());
    board_->set(prefix_ + "threshold_m", config::number(f.threshold_m));
  }
  // commands are task events too, at the step that first uses them
  switch (a.kind) {
    case sim::ParamKind::model:
      f.event.set_kind(msgs::TaskEvent::CONDITION);
      f.event.set_detail("computer model " + model_name());
      break;
    case sim::ParamKind::reset:
      f.event.set_kind(msgs::TaskEvent::RESET);
      f.event.set_detail("reset");
      break;
    case sim::ParamKind::reposition:
      f.event.set_kind(msgs::TaskEvent::RESET);
      f.event.set_detail("repositioned at the start");
      break;
    case sim::ParamKind::trial_start: f.event.set_kind(msgs::TaskEvent::TRIAL_START); break;
    case sim::ParamKind::trial_stop:
      f.event.set_kind(msgs::TaskEvent::TRIAL_END);
      f.event.set_detail("stopped");
      break;
    case sim::ParamKind::number: return;
  }
  f.event.set_condition(model_name());
}

const std::string& ParamPort::model_name_at(std::int64_t time_ns) const {
  for (auto it = names_.rbegin(); it != names_.rend(); ++it) {
    if (it->first <= time_ns) return it->second;
  }
  return names_.front().second;
}

void ParamPort::stepped(std::uint64_t step, std::uint64_t state_seq, std::int64_t state_ns) {
  for (auto it = in_flight_.begin(); it != in_flight_.end();) {
    InFlight& f = it->second;
    if (f.step == 0 || f.step > step) {
      ++it;
      continue;
    }
    f.ack.set_state_seq(state_seq);
    publish(std::move(f.ack));
    if (f.event.kind() != msgs::TaskEvent::KIND_UNSPECIFIED) {
      f.event.set_time_ns(state_ns);
      events_.publish(f.event);
    }
    it = in_flight_.erase(it);
  }
}

void ParamPort::refuse(std::uint64_t request_id, const std::string& name, const std::string& reason) {
  msgs::ParamAck a;
  a.set_request_id(request_id);
  a.set_applied(false);
  a.set_reason(reason);
  a.set_name(name);
  publish(std::move(a));
}

void ParamPort::publish(msgs::ParamAck a) {
  acks_.publish(a);
  answered_.push_back(std::move(a));
  if (answered_.size() > kAnswersKept) answered_.pop_front();
}

ParamClient::ParamClient(const std::string& endpoint, std::string source, const bus::ClientKeys& keys) : sender_(endpoint, std::move(source), keys) {
  // ids from a random start: several senders on one graph do not collide
  std::random_device rd;
  next_id_ = (std::uint64_t{rd()} << 32 | rd()) | 1u;
}

std::uint64_t ParamClient::send(msgs::ParamUpdate update) {
  const std::uint64_t id = update.request_id() != 0 ? update.request_id() : next_id_++;
  const std::int64_t now = rt::now_ns();
  update.set_request_id(id);
  sender_.send(kParamSet, update);
  pending_[id] = {std::move(update), now, now, kFirstResend_ns};
  return id;
}

std::vector<ParamAnswer> ParamClient::tick(std::int64_t now_ns) {
  std::vector<ParamAnswer> given_up;
  for (auto it = pending_.begin(); it != pending_.end();) {
    Pending& p = it->second;
    if (now_ns - p.first_ns >= kTimeout_ns) {
      given_up.push_back({it->first, p.update.name(), false,
                          "no answer in 5 s: no simulator of that name in the graph, or the graph is not running", false, 0});
      it = pending_.erase(it);
      continue;
    }
    if (now_ns - p.last_ns >= p.wait_ns) {
      sender_.send(kParamSet, p.update);
      p.last_ns = now_ns;
      p.wait_ns = std::min(2 * p.wait_ns, kResend_ns);
    }
    ++it;
  }
  return given_up;
}

const msgs::ParamValues::Param* find_param(const std::vector<msgs::ParamValues>& boards, const std::string& name) {
  for (const msgs::ParamValues& b : boards) {
    for (const msgs::ParamValues::Param& e : b.params()) {
      if (e.name() == name) return &e;
    }
  }
  return nullptr;
}

std::string no_such_param(const std::vector<msgs::ParamValues>& boards, const std::string& name) {
  std::vector<std::string> names;
  for (const msgs::ParamValues& b : boards) {
    for (const msgs::ParamValues::Param& e : b.params()) names.push_back(e.name());
  }
  return "no parameter '" + name + "' in the graph" + config::did_you_mean(name, names) + "\n  fix: enact param list shows them all";
}

std::string fixed_refusal(const std::vector<msgs::ParamValues>& boards, const std::string& name) {
  const msgs::ParamValues::Param* e = find_param(boards, name);
  if (!e || e->live()) return "";
  return "it cannot change while the graph runs (now \"" + e->value() + "\")\n  fix: change it in the launch file (or its param_file) and launch again";
}

std::string answer_text(const ParamAnswer& a) {
  if (a.applied) return a.state_seq > 0 ? "applied from ffd/state seq " + std::to_string(a.state_seq) : "applied";
  return a.answered ? "refused: " + a.reason : a.reason;
}

std::optional<ParamAnswer> ParamClient::take(const msgs::ParamAck& ack) {
  const auto it = pending_.find(ack.request_id());
  if (it == pending_.end()) return std::nullopt;
  ParamAnswer answer{ack.request_id(), it->second.update.name(), ack.applied(), ack.reason(), true, ack.state_seq()};
  pending_.erase(it);
  return answer;
}

}  // namespace enact::graph
