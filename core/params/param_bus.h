#pragma once
// param/set and param/ack on the bus (docs/parameters.md). The simulator's end, ParamPort,
// is the same for enact-sim and enact-rt: requests in (from the attach point's inbound
// publisher), checked by a sim::ParamPlanner on a thread of the port's own (planning may read
// a computer model's YAML file and copies the model: never on a loop thread), changes out to
// whoever applies them between steps, acks and task events back. The sender's end, ParamClient, is the viewer's and
// `enact param set`'s: a request goes up through the attach point and is sent again until
// its ParamAck comes (the sim answers a repeated request without applying it twice).
#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <semaphore>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/bus/attach.h"
#include "core/bus/bytes.h"
#include "core/bus/typed.h"
#include "core/params/param_board.h"
#include "core/rt/spsc_queue.h"
#include "core/sim/params.h"
#include "core/sim/simulator.h"
#include "msgs/param_update.pb.h"
#include "msgs/task_event.pb.h"

namespace enact::graph {

// a ParamUpdate's value as the simulator reads it
sim::ParamValue value_of(const msgs::ParamUpdate& m);

// VALUE as typed on a command line: a number, true / false (a flag), or text
void set_value(msgs::ParamUpdate& m, const std::string& value);
// the value held in `value` (none set: none sent)
void set_value(msgs::ParamUpdate& m, const sim::ParamValue& value);

class ParamPort {
 public:
  // for `simulator` (configured, its model not being written by another thread while this
  // runs) named `prefix` (its node or component name): requests named "<prefix>.<param>"
  // are its own, others are ignored (another node's). Subscribes to param/set at the
  // graph's inbound publisher (node_endpoint(kInboundNode)), acks on param/ack through
  // `out`, task events of applied commands through `events`, and, with a `board`, the values
  // in force of its live parameters there (all must outlive the port).
  ParamPort(const sim::Simulator& simulator, std::string prefix, bus::BytePublisher& out, bus::Publisher<msgs::TaskEvent>& events,
            ParamBoard* board = nullptr);
  ~ParamPort();
  ParamPort(const ParamPort&) = delete;
  ParamPort& operator=(const ParamPort&) = delete;

  // the next accepted change to apply (non-blocking; nullopt when none is planned yet, or when
  // sim::kMaxParamsInFlight changes are not applied yet: a loop's queue of that capacity never
  // overflows). New requests go to the planning thread here; refused ones are acked here
  // (applied ones by stepped()); a repeated request (same request_id) is not planned again:
  // its ack is sent again once known. Reads no file, whatever the request.
  std::optional<sim::ParamChange> next();

  // the loop applied `a`: its ack and task event wait for the step that first uses it
  void applied(const sim::ParamApplied& a);
  // the simulator's step `step` (ParamApplied::step's count) ran on the device state
  // `state_seq` stamped `state_ns`: ack the applied changes it was the first to use with that
  // seq, and publish their task events at that time (cheap when none waits: call it after
  // every step)
  void stepped(std::uint64_t step, std::uint64_t state_seq, std::int64_t state_ns);

  // the computer model's name as of the last applied change
  const std::string& model_name() const { return names_.back().second; }
  // its name at `time_ns` (the clock of ParamApplied::time_ns), for what the loop did then:
  // right once every change applied until then was passed to applied()
  const std::string& model_name_at(std::int64_t time_ns) const;

  // requests received, for NodeStatus
  const bus::ByteSubscriber& subscriber() const { return in_bytes_; }

 private:
  // a request for the planning thread, and its plan back (trivially copyable: SPSC queues)
  static constexpr std::size_t kMaxText = 1023;
  struct PlanRequest {
    std::uint64_t id = 0;
    char name[64] = {};  // without the prefix
    msgs::ParamUpdate::ValueCase value_case = msgs::ParamUpdate::VALUE_NOT_SET;
    double number = 0.0;
    bool flag = false;
    char text[kMaxText + 1] = {};
  };
  struct Plan {
    std::uint64_t id = 0;
    bool accepted = false;
    sim::ParamChange change;
    char reason[512] = {};                    // refused
    char model[sim::kMaxModelName + 1] = {};  // accepted: the computer model's name after it
    double threshold_m = 0.0;                 // and its threshold
  };
  void submit(std::uint64_t id);  // request_ to the planning thread (or refused at once)
  void plan_all();                // the planning thread
  std::optional<sim::ParamChange> take(const Plan& plan);
  void refuse(std::uint64_t request_id, const std::string& name, const std::string& reason);

  sim::ParamPlanner planner_;  // the planning thread's once it runs
  std::string prefix_;
  bus::ByteSubscriber in_bytes_;
  bus::Subscriber<msgs::ParamUpdate> in_;
  bus::Publisher<msgs::ParamAck> acks_;
  bus::Publisher<msgs::TaskEvent>& events_;
  msgs::ParamUpdate request_;
  std::deque<std::pair<std::int64_t, std::string>> names_;  // the model's name from a time on
  ParamBoard* board_;
  struct InFlight {
    msgs::ParamUpdate request;
    std::string model;     // the model name it sets ("" if none)
    double threshold_m = 0.0;  // the threshold it sets (a model's)
    msgs::ParamAck ack;    // its ack, but for the step
    msgs::TaskEvent event; // its task event, but for the time (kind UNKNOWN: none)
    std::uint64_t step = 0;  // applied: the step that first uses it (0: not applied yet)
  };
  void publish(msgs::ParamAck a);

  std::map<std::uint64_t, InFlight> in_flight_;  // by request id
  std::deque<msgs::ParamAck> answered_;          // the last answers, for repeated requests
  rt::SpscQueue<PlanRequest, sim::kMaxParamsInFlight> to_plan_;
  rt::SpscQueue<Plan, sim::kMaxParamsInFlight> planned_;
  std::counting_semaphore<> wake_{0};
  std::atomic<bool> stopping_{false};
  std::thread planning_;  // last: starts once everything above is made
};

// the parameter named `name` ("<node>.<param>") in the nodes' ParamValues, or nullptr
const msgs::ParamValues::Param* find_param(const std::vector<msgs::ParamValues>& boards, const std::string& name);

// "no parameter 'NAME' in the graph", the closest names and the fix
std::string no_such_param(const std::vector<msgs::ParamValues>& boards, const std::string& name);

// why a change of `name` is refused before it is sent (enact param set, the Foxglove bridge):
// its node declares it not live (no node would answer); "" when it may be sent (the node
// decides then)
std::string fixed_refusal(const std::vector<msgs::ParamValues>& boards, const std::string& name);

// the answer to one request, as the sender sees it
struct ParamAnswer {
  std::uint64_t request_id = 0;
  std::string name;      // as sent, e.g. "sim.stiffness_n_per_m"
  bool applied = false;
  std::string reason;    // refused: why; no answer in time: says so
  bool answered = false; // false: the graph did not answer in time
  std::uint64_t state_seq = 0;  // applied: the ffd/state seq whose step first used it (0: not said)
};

// what the command line prints after a request's name: "applied from ffd/state seq N",
// "refused: REASON", or why no answer came
std::string answer_text(const ParamAnswer& answer);

class ParamClient {
 public:
  // sends through the attach point at `endpoint` with `keys` (none: plain); `source` names
  // the sender in headers
  ParamClient(const std::string& endpoint, std::string source, const bus::ClientKeys& keys = {});

  // sends `update` (name and value set) with its request id, a fresh one when it has none
  // (a Foxglove client's own id is kept: it sees the answer on param/ack); returns the id
  std::uint64_t send(msgs::ParamUpdate update);
  // resends the requests still unanswered: 10 ms after the first send (a request sent before
  // the connection to the attach point is up is lost), then twice as long each time, at most
  // every 250 ms; the ones older than 5 s are given up and returned, unanswered
  std::vector<ParamAnswer> tick(std::int64_t now_ns);
  // a ParamAck received on param/ack: the answer when it is one of ours still unanswered
  std::optional<ParamAnswer> take(const msgs::ParamAck& ack);

  static constexpr std::int64_t kFirstResend_ns = 10'000'000;
  static constexpr std::int64_t kResend_ns = 250'000'000;
  static constexpr std::int64_t kTimeout_ns = 5'000'000'000;

 private:
  struct Pending {
    msgs::ParamUpdate update;
    std::int64_t first_ns = 0;
    std::int64_t last_ns = 0;
    std::int64_t wait_ns = kFirstResend_ns;  // until the next resend
  };

  bus::AttachSender sender_;
  std::uint64_t next_id_;
  std::map<std::uint64_t, Pending> pending_;
};

}  // namespace enact::graph
