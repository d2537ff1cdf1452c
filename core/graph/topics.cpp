#include "core/graph/topics.h"

#include <unistd.h>

#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"

namespace enact::graph {

std::vector<TopicDecl> topics_of(const std::string& exec) {
  const TopicDecl state{kDeviceState, msgs::DeviceState::descriptor()->full_name()};
  const TopicDecl force{kForceCommand, msgs::ForceCommand::descriptor()->full_name()};
  const TopicDecl frame{kTactileFrame, msgs::TactileFrame::descriptor()->full_name()};
  const TopicDecl shown{kTactileShown, msgs::TactileShown::descriptor()->full_name()};
  const TopicDecl scene{kSceneState, msgs::SceneState::descriptor()->full_name()};
  const TopicDecl event{kTaskEvent, msgs::TaskEvent::descriptor()->full_name()};
  const TopicDecl status{kNodeStatus, msgs::NodeStatus::descriptor()->full_name()};
  const TopicDecl ack{kParamAck, msgs::ParamAck::descriptor()->full_name()};
  if (exec == "enact-ffd") return {state, status};
  if (exec == "enact-sim") return {force, frame, scene, event, status, ack};
  if (exec == "enact-tactile") return {shown, status};
  if (exec == "enact-rt") return {state, force, frame, shown, scene, event, status, ack};
  return {};
}

std::string attach_file() { return "/tmp/enact-" + std::to_string(getuid()) + "/attach"; }

}  // namespace enact::graph
