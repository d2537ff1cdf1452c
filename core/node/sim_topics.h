#pragma once
// The simulator's topics, published alike by enact-sim (node::Sim) and by the co-located
// enact-rt (node::Container), which runs the same simulator: one declaration for both
// (node/status is the host's: node::Host::publish_status).
#include "core/bus/typed.h"
#include "core/graph/topics.h"
#include "msgs/force_command.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/sim_keyframe.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"

namespace enact::node {

struct SimTopics {
  explicit SimTopics(bus::BytePublisher& out)
      : force_pub(out, graph::kForceCommand),
        frame_pub(out, graph::kTactileFrame),
        scene_pub(out, graph::kSceneState),
        event_pub(out, graph::kTaskEvent),
        keyframe_pub(out, graph::kSimKeyframe) {}
  bus::Publisher<msgs::ForceCommand> force_pub;
  bus::Publisher<msgs::TactileFrame> frame_pub;
  bus::Publisher<msgs::SceneState> scene_pub;
  bus::Publisher<msgs::TaskEvent> event_pub;
  bus::Publisher<msgs::SimKeyframe> keyframe_pub;
};

}  // namespace enact::node
