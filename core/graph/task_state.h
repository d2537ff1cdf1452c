#pragma once
// The trial as it stands, on task/state (msgs/task_state.proto): the simulator's node (enact-sim)
// and the co-located container's publisher thread (enact-rt) feed it every step and every
// applied change; it publishes at 10 Hz and at once on every change of phase, falls or
// model. The attach point keeps the last one for observers that come late.
#include <cstdint>
#include <string>

#include "core/bus/typed.h"
#include "core/sim/params.h"
#include "core/sim/simulator.h"
#include "msgs/task_state.pb.h"

namespace enact::graph {

class TaskStateTracker {
 public:
  // publishes on task/state through `out` (which must outlive it)
  explicit TaskStateTracker(bus::BytePublisher& out);

  // one step at `time_ns` (the clock of the step's task events) and what it made
  void step(std::int64_t time_ns, const sim::StepOutput& o);
  // the loop applied a change of this kind: reset and trial start begin a trial, trial stop
  // ends it
  void applied(sim::ParamKind kind);
  // publishes when something changed, or 100 ms after the last one (`now_ns`: monotonic);
  // `model`: the computer model in force
  void publish_due(std::int64_t now_ns, const std::string& model);

  const msgs::TaskState& state() const { return msg_; }

 private:
  void begin_trial();

  bus::Publisher<msgs::TaskState> pub_;
  msgs::TaskState msg_;
  std::int64_t start_ns_ = -1;      // the trial's first step (-1: at the next step)
  std::int64_t last_ns_ = 0;        // the last step
  std::int64_t fall_since_ns_ = -1; // an open counted fall began here
  std::int64_t closed_out_ns_ = 0;  // time out of the falls already ended
  std::int64_t next_ns_ = 0;        // the next periodic publication
  bool changed_ = true;
};

}  // namespace enact::graph
