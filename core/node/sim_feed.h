#pragma once
// The simulator's half beside its loop, one for both hosts: enact-sim (node::Sim) and the
// co-located enact-rt (node::Container) run the same simulator on a loop thread and this on
// another. It takes parameter requests to the loop (planned on the ParamPort's own thread:
// the loop only swaps them in), acks what the loop applied, and publishes what each step
// made for observers: ffd/force, tactile/frame, task/event, task/state, sim/scene and
// sim/keyframe (node/status is the host's: node::Host::publish_status). Nothing here runs on
// the loop thread; everything it takes from there is trivially copyable.
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "core/bus/typed.h"
#include "core/graph/messages.h"
#include "core/graph/stop.h"
#include "core/graph/task_state.h"
#include "core/graph/topics.h"
#include "core/node/sim_step.h"
#include "core/params/param_bus.h"
#include "msgs/force_command.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/sim_keyframe.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"

namespace enact::node {

// a scene snapshot the loop took at one tick (its time names the computer model in force)
struct Scene {
  std::int64_t tick_ns = 0;
  graph::SceneSnapshot snap;
};

// into a queue to the feed's thread: in real time what does not fit is lost (false: counted
// by the caller); in simulated time the loop waits for room, so observers see every step
template <typename Queue, typename Item>
bool deliver(Queue& queue, const Item& item, bool simulated) {
  if (!simulated) return queue.try_push(item);
  while (!queue.try_push(item)) {
    if (graph::stop_requested()) return false;
    std::this_thread::yield();
  }
  return true;
}

// a keyframe the loop saved after one of its steps (sized before the loop: saving allocates
// nothing), for the feed, which publishes it right after that step's messages: replay goes
// on from there with the next sample
class KeyframeSlot {
 public:
  // before the loop
  void size(const sim::Simulator& s) { s.save(keyframe_); }
  // the loop's thread: after step `step`, unless the last one still waits
  void save(const sim::Simulator& s, std::uint64_t step) {
    if (full_.load(std::memory_order_acquire)) return;
    s.save(keyframe_);
    step_ = step;
    full_.store(true, std::memory_order_release);
  }
  // the feed's thread, once step `step` is published: `publish` the keyframe saved after it
  // (one whose step was lost to a full queue is let go)
  template <typename F>
  void after(std::uint64_t step, F&& publish) {
    if (!full_.load(std::memory_order_acquire) || step_ > step) return;
    if (step_ == step) publish(keyframe_);
    full_.store(false, std::memory_order_release);
  }

 private:
  sim::Keyframe keyframe_;
  std::uint64_t step_ = 0;
  std::atomic<bool> full_{false};
};

class SimFeed {
 public:
  // for `simulator` (configured, its model copied here before its loop starts) named
  // `name`, publishing through `out`; `board`: its live parameters' values; rows x cols: the
  // tactile frame's grid; `simulated`: the graph's clock is simulated (the answer says when
  // the task is over)
  SimFeed(const sim::Simulator& simulator, const std::string& name, bus::BytePublisher& out, graph::ParamBoard* board, int rows, int cols,
          bool simulated);

  // requests planned since the last call, into the loop's queue
  void intake(graph::ParamQueue& changes);
  // what the loop applied, acked once the step that first used it is published
  void take_applied(graph::AppliedQueue& applied);
  // one step of the loop, answering the device state `state_seq`: ffd/force, tactile/frame
  // and task/event as the step made them, the acks it was the first to use
  void step(const graph::Observation& o, std::uint64_t state_seq);
  void scene(const Scene& s);
  void keyframe(const sim::Keyframe& k, const physics::Model& model);
  // task/state when due (now_ns: monotonic)
  void due(std::int64_t now_ns);
  // task/event of a stop the host made (duration_s over): TRIAL_END "stopped" at time_ns
  void stopped(std::int64_t time_ns);
  // an event of the node's own, on task/event (its condition: the model in force)
  void say_event(msgs::TaskEvent::Kind kind, std::int64_t time_ns, const std::string& detail);

  graph::ParamPort& params() { return params_; }
  // the seq of the last tactile/frame published (0: none yet)
  std::uint64_t frame_seq() const { return frame_seq_; }

  // the answer to the state `state_seq` for step o, as the loop sends it over its own hop
  // and as this publishes it (allocates nothing once `m` was filled once)
  static void answer(msgs::ForceCommand& m, const graph::Observation& o, std::uint64_t state_seq, bool simulated);

 private:
  bus::Publisher<msgs::ForceCommand> force_pub_;
  bus::Publisher<msgs::TactileFrame> frame_pub_;
  bus::Publisher<msgs::SceneState> scene_pub_;
  bus::Publisher<msgs::TaskEvent> event_pub_;
  bus::Publisher<msgs::SimKeyframe> keyframe_pub_;
  graph::ParamPort params_;
  graph::TaskStateTracker task_state_;
  const int rows_, cols_;
  const bool simulated_;
  std::uint64_t frame_seq_ = 0;
  sim::ParamApplied done_;
  msgs::ForceCommand force_;
  msgs::TactileFrame frame_;
  msgs::SceneState scene_;
  msgs::TaskEvent event_;
  msgs::SimKeyframe keyframe_;
};

}  // namespace enact::node
