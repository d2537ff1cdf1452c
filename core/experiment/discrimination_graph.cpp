#include "core/experiment/discrimination_graph.h"

#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include "core/bus/typed.h"
#include "core/config/format.h"
#include "core/experiment/plan_file.h"
#include "core/experiment/trial_graph.h"
#include "core/params/node_params.h"
#include "core/params/param_bus.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"
#include "msgs/device_state.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/task_event.pb.h"

namespace enact::experiment {
namespace {

namespace fs = std::filesystem;

// while the subject is asked, their answer is polled this often
constexpr std::int64_t kPollEvery_ns = 20'000'000;
// the simulator's name in the trial graphs (trial_rt.yaml's component, trial.yaml's node)
constexpr const char* kSimulator = "sim";

// the launch arguments of a trial's graph: the condition's model, the recording, and a limit
// past the two intervals and the answer
launch::LaunchDescription trial_graph(const DiscriminationSpec& spec, const Condition& condition, const std::string& recording) {
  std::map<std::string, std::string> a(spec.launch_args.begin(), spec.launch_args.end());
  a["model"] = condition.model;
  a["recording"] = recording;
  a["limit_s"] = config::number(2.0 * spec.interval_s + spec.answer_limit_s);
  return load_trial_graph(spec.launch, a, spec.clock);
}

// the graph's clock as the runner sees it, from the device states: the stamp of each recent
// tick (a loop that missed deadlines skips ticks: its seqs run behind its stamps)
class GraphTime {
 public:
  GraphTime() : kept_(kKept) {}
  void saw(const msgs::DeviceState& s) {
    if (!seen_) first_seq_ = s.header().seq(), first_ns_ = s.header().stamp_ns();
    seen_ = true;
    seq_ = s.header().seq();
    now_ns_ = s.header().stamp_ns();
    buttons_ = s.buttons();
    kept_[seq_ % kKept] = {seq_, now_ns_};
  }
  bool seen() const { return seen_; }
  std::uint64_t seq() const { return seq_; }
  std::int64_t now_ns() const { return now_ns_; }
  std::uint32_t buttons() const { return buttons_; }
  // the stamp of tick `seq`: as received, else from the latest at the mean period so far
  std::int64_t at(std::uint64_t seq) const {
    const auto& [kept_seq, kept_ns] = kept_[seq % kKept];
    if (kept_seq == seq) return kept_ns;
    if (seq_ <= first_seq_) return now_ns_;
    const double period_ns = static_cast<double>(now_ns_ - first_ns_) / static_cast<double>(seq_ - first_seq_);
    return now_ns_ + std::llround((static_cast<double>(seq) - static_cast<double>(seq_)) * period_ns);
  }

 private:
  static constexpr std::size_t kKept = 1 << 15;  // 6.5 s at 5 kHz
  std::vector<std::pair<std::uint64_t, std::int64_t>> kept_;  // (seq, stamp) by seq % kKept
  bool seen_ = false;
  std::uint64_t first_seq_ = 0, seq_ = 0;
  std::int64_t first_ns_ = 0, now_ns_ = 0;
  std::uint32_t buttons_ = 0;
};

class GraphTrial {
 public:
  GraphTrial(const DiscriminationSpec& spec, const Presentation& trial, const std::string& folder, AnswerSource& answers, RunnerUi& ui)
      : spec_(spec), trial_(trial), answers_(answers), ui_(ui), person_(!spec.virtual_observers) {
    const std::string stem = folder + "/" + trial_stem(trial);
    recording_ = stem + ".mcap";
    log_ = stem + ".log";
  }

  GraphAnswer run() {
    std::error_code ec;
    fs::remove(recording_, ec);  // an abandoned attempt
    launch::LaunchDescription graph = trial_graph(spec_, trial_.block->condition, recording_);
    simulated_ = graph.clock == rt::GraphClock::simulated;
    const int code = run_trial_graph(spec_.name + "/" + trial_.block->subject + "_" + trial_.block->condition.label, spec_.launch, std::move(graph), log_,
                                     [this](GraphRun& g) { watch(g); });
    GraphAnswer a;
    if (chosen_ != 0 && fs::exists(recording_)) return {GraphAnswer::Outcome::answered, chosen_, response_time_s_, ""};
    if (!problem_.empty()) a.problem = problem_ + " (see " + log_ + ")";
    else if (code == 0 && !stop_sent_) a.outcome = GraphAnswer::Outcome::interrupted;
    else a.problem = "the graph failed (exit " + std::to_string(code) + "; see " + log_ + ")";
    return a;
  }

 private:
  enum class Phase : std::uint8_t { starting, setting, exploring, asking, answered, done };

  // the value of the compared parameter in interval `i` (1 or 2)
  double value(int i) const { return spec_.reference + (i == trial_.reference_interval ? 0.0 : trial_.level); }
  std::string value_text(int i) const {
    return spec_.parameter + " " + config::number(value(i)) + (i == trial_.reference_interval ? " (reference)" : " (comparison)");
  }

  void stop(GraphRun& g) {
    stop_sent_ = true;
    g.stop();
  }
  // the trial cannot be answered: it runs again
  void fail(GraphRun& g, const std::string& why) {
    if (phase_ == Phase::answered || phase_ == Phase::done) return;
    problem_ = why;
    phase_ = Phase::done;
    stop(g);
  }

  // the runner's side of the trial while the supervisor runs the graph: the device states
  // give the graph's time, the acks say where each interval began
  void watch(GraphRun& g) {
    bus::Publisher<msgs::TaskEvent> events_out(g.out, graph::kTaskEvent);
    bus::ByteSubscriber in;
    bus::Subscriber<msgs::TaskEvent> events(in, graph::kTaskEvent);
    bus::Subscriber<msgs::ParamAck> acks(in, graph::kParamAck);
    bus::Subscriber<msgs::DeviceState> states(in, graph::kDeviceState);
    in.connect(g.endpoint);
    graph::ParamClient params(g.endpoint, kRunnerNode);
    publish_ = &events_out;
    bus::RawMessage raw;
    msgs::TaskEvent event;
    msgs::ParamAck ack;
    msgs::DeviceState state;
    const std::int64_t began_ns = rt::now_ns();
    const double limit_s = 2.0 * spec_.interval_s + spec_.answer_limit_s;
    while (!g.finished()) {
      if (in.receive(raw, 20)) {
        if (states.accept(raw, state)) {
          time_.saw(state);
        } else if (acks.accept(raw, ack)) {
          if (const auto answer = params.take(ack)) began_interval(g, *answer);
        } else if (events.accept(raw, event)) {
          took(g, event);
        }
      }
      for (const graph::ParamAnswer& lost : params.tick(rt::now_ns())) fail(g, lost.name + ": " + graph::answer_text(lost));
      next(g, params);
      if (phase_ == Phase::answered && seconds_since(answered_ns_) > kDrain_s) finish(g);
      if (!simulated_ && seconds_since(began_ns) > limit_s + kDrain_s) fail(g, "no answer in time");
    }
    publish_ = nullptr;
  }

  // what the trial does next, given what came in
  void next(GraphRun& g, graph::ParamClient& params) {
    if (phase_ == Phase::starting && g.ready() && g.out.has_subscribers(graph::kTaskEvent)) {
      // announced once the attach point forwards task/event from here (so does the logger's)
      announce(msgs::TaskEvent::CONDITION, rt::now_ns(), "discrimination");
      announce(msgs::TaskEvent::TRIAL_START, rt::now_ns(),
               trial_.procedure + ": level " + config::number(trial_.level) + ", reference in interval " + std::to_string(trial_.reference_interval));
      set_interval(params, 1);
    }
    if (phase_ == Phase::exploring && time_.seen() && time_.now_ns() - start_ns_ >= std::llround(spec_.interval_s * 1e9)) {
      if (interval_ == 1) {
        set_interval(params, 2);
      } else {
        end_ns_ = time_.now_ns();
        announce(msgs::TaskEvent::INTERVAL_END, end_ns_, "interval 2 ended at ffd/state seq " + std::to_string(time_.seq()));
        phase_ = Phase::asking;
        if (person_) ui_.note("which interval had the larger " + spec_.parameter + "? 1 or 2 (+ Enter), or the device's button 1 or 2");
      }
    }
    if (phase_ == Phase::asking && rt::now_ns() >= next_poll_ns_) {
      // asked at once (an observer answers there), then about every 20 ms
      next_poll_ns_ = rt::now_ns() + kPollEvery_ns;
      const int chosen = answers_.answer(trial_, time_.buttons());
      if (chosen == 1 || chosen == 2) {
        chosen_ = chosen;
        response_time_s_ = static_cast<double>(time_.now_ns() - end_ns_) * 1e-9;
        announce(msgs::TaskEvent::ANSWER, time_.now_ns(), "interval " + std::to_string(chosen) + ", response time " + config::number(response_time_s_) + " s");
        phase_ = Phase::answered;
        answered_ns_ = rt::now_ns();
      }
    }
  }

  // a task event from the graph: the answer back from the attach point (so the logger has it
  // too: the graph may stop), or the graph's end of the trial before the answer
  void took(GraphRun& g, const msgs::TaskEvent& event) {
    if (event.header().source() == kRunnerNode) {
      if (event.kind() == msgs::TaskEvent::ANSWER && phase_ == Phase::answered) finish(g);
    } else if (event.kind() == msgs::TaskEvent::TRIAL_END) {
      fail(g, "the graph ended the trial before the answer (" + event.detail() + "): no answer within answer_limit_s " + config::number(spec_.answer_limit_s) + " s");
    }
  }

  void finish(GraphRun& g) {
    phase_ = Phase::done;
    stop(g);
  }

  // interval `i`'s value on param/set, as enact param set sends it
  void set_interval(graph::ParamClient& params, int i) {
    msgs::ParamUpdate update;
    update.set_name(std::string(kSimulator) + "." + spec_.parameter);
    update.set_number(value(i));
    params.send(update);
    interval_ = i;
    phase_ = Phase::setting;
  }

  // the simulator applied interval_'s value from the step of `answer.state_seq`: the interval
  // begins there (and the one before ends)
  void began_interval(GraphRun& g, const graph::ParamAnswer& answer) {
    if (!answer.applied) return fail(g, "the simulator refused " + answer.name + " = " + config::number(value(interval_)) + ": " + answer.reason);
    const std::int64_t at_ns = time_.at(answer.state_seq);
    const std::string seq = " at ffd/state seq " + std::to_string(answer.state_seq);
    if (interval_ == 2) announce(msgs::TaskEvent::INTERVAL_END, at_ns, "interval 1 ended" + seq);
    announce(msgs::TaskEvent::INTERVAL_START, at_ns, "interval " + std::to_string(interval_) + ": " + value_text(interval_) + " from" + seq);
    if (person_) ui_.note("interval " + std::to_string(interval_));
    start_ns_ = at_ns;
    phase_ = Phase::exploring;
  }

  void announce(msgs::TaskEvent::Kind kind, std::int64_t time_ns, const std::string& detail) {
    event_.Clear();
    event_.set_kind(kind);
    event_.set_time_ns(time_ns);
    event_.set_condition(trial_.block->condition.label);
    event_.set_subject(trial_.block->subject);
    event_.set_trial(static_cast<std::uint32_t>(trial_.trial));
    event_.set_detail(detail);
    publish_->publish(event_);
  }

  const DiscriminationSpec& spec_;
  const Presentation& trial_;
  AnswerSource& answers_;
  RunnerUi& ui_;
  const bool person_;
  std::string recording_, log_;
  bool simulated_ = false;
  // the watching thread's (run() reads them once it has joined)
  Phase phase_ = Phase::starting;
  GraphTime time_;
  int interval_ = 0;               // the interval set or running
  std::int64_t start_ns_ = 0;      // its first tick's stamp
  std::int64_t end_ns_ = 0;        // the last interval's end
  int chosen_ = 0;
  double response_time_s_ = 0.0;
  std::int64_t next_poll_ns_ = 0, answered_ns_ = 0;  // on rt::now_ns()
  std::string problem_;
  std::atomic<bool> stop_sent_{false};
  msgs::TaskEvent event_;
  bus::Publisher<msgs::TaskEvent>* publish_ = nullptr;
};

}  // namespace

std::string trial_stem(const Presentation& trial) {
  char number[16];
  std::snprintf(number, sizeof number, "_t%03zu", trial.trial + 1);
  std::string stem = "s";
  stem += file_safe(trial.block->subject) + "_" + file_safe(trial.block->condition.label) + number;
  return stem;
}

GraphAnswer run_graph_trial(const DiscriminationSpec& spec, const Presentation& trial, const std::string& folder, AnswerSource& answers, RunnerUi& ui) {
  return GraphTrial(spec, trial, folder, answers, ui).run();
}

std::vector<std::string> check_discrimination_graphs(const DiscriminationSpec& spec, const std::string& out) {
  std::vector<std::string> problems;
  if (!spec.on_graph()) return problems;
  for (const Condition& c : spec.conditions) {
    for (const std::string& p : graph::check_graph(trial_graph(spec, c, out + "/trials/check.mcap"))) problems.push_back("condition " + c.label + ": " + p);
  }
  return problems;
}

}  // namespace enact::experiment
