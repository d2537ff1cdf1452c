#include "core/bus/schema.h"

#include <set>
#include <string>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

#include "msgs/common.pb.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/graph.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"
#include "msgs/sim_keyframe.pb.h"
#include "msgs/task_state.pb.h"

namespace enact::bus {
namespace {

using google::protobuf::FileDescriptor;
using google::protobuf::FileDescriptorSet;

// adds `file` after its imports, once
void add_file(const FileDescriptor& file, std::set<std::string>& added, FileDescriptorSet& set) {
  if (added.contains(file.name())) return;
  for (int i = 0; i < file.dependency_count(); ++i) add_file(*file.dependency(i), added, set);
  added.insert(file.name());
  file.CopyTo(set.add_file());
}

}  // namespace

std::string msgs_descriptor_set() {
  // one type per msgs/*.proto file. Naming them here also links every file's generated code
  // into the program (enact_msgs is a static library). A new .proto file goes in this list;
  // tests/bus/schema_test.cpp checks that none is missing.
  const google::protobuf::Descriptor* const one_type_per_file[] = {
      msgs::Header::descriptor(),       msgs::DeviceState::descriptor(), msgs::ForceCommand::descriptor(),
      msgs::TactileFrame::descriptor(), msgs::SceneState::descriptor(),  msgs::TaskEvent::descriptor(),
      msgs::ParamUpdate::descriptor(),  msgs::NodeStatus::descriptor(),  msgs::GraphInfo::descriptor(),
      msgs::TaskState::descriptor(),    msgs::SimKeyframe::descriptor(),
  };
  std::set<std::string> added;
  FileDescriptorSet set;
  for (const auto* type : one_type_per_file) add_file(*type->file(), added, set);
  return set.SerializeAsString();
}

std::string descriptor_set_of(const google::protobuf::Descriptor& type) {
  std::set<std::string> added;
  FileDescriptorSet set;
  add_file(*type.file(), added, set);
  return set.SerializeAsString();
}

}  // namespace enact::bus
