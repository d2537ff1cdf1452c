// enact export FILE --foxglove OUT.mcap: a recording with the scene for Foxglove's 3D panel
// (foxglove/scene, foxglove.SceneUpdate), made by the converter the live bridge uses.
#include <cstdio>
#include <optional>

#include "core/bus/schema.h"
#include "core/config/yaml.h"
#include "core/foxglove/scene.h"
#include "core/graph/topics.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/mcap_copy.h"

namespace enact::cli {

int export_foxglove(const Args& a) {
  if (a.positional.size() != 1) throw UsageError("give FILE and --foxglove OUT.mcap");
  const std::string out = a.get("foxglove");
  if (out == a.positional[0]) throw UsageError("write the Foxglove copy next to the recording, not over it");
  record::Reader r(a.positional[0]);
  for (const auto& [id, c] : r.channels()) {
    if (c.topic == foxglove::kSceneTopic) throw config::Error(r.path() + ": already has " + foxglove::kSceneTopic + "\n  fix: open it in Foxglove as it is");
  }
  // the scene file the logger kept with the recording, and the files it reads beside it
  const std::optional<graph::NamedScene> scene = graph::find_scene(r.attachments(), record::name_of, record::data_of);
  if (!scene) {
    throw config::Error(r.path() + ": no scene file attached, so no 3D scene can be drawn\n  fix: record a graph started by `enact launch` (its logger attaches the scene)");
  }
  const foxglove::SceneConverter converter = foxglove::converter_for(*scene);
  record::Writer w(out);
  const auto schema = w.add_schema(::foxglove::SceneUpdate::descriptor()->full_name(), "protobuf", bus::descriptor_set_of(*::foxglove::SceneUpdate::descriptor()));
  const auto channel = w.add_channel(schema, foxglove::kSceneTopic, "protobuf");
  msgs::SceneState state;
  ::foxglove::SceneUpdate update;
  std::uint32_t scenes = 0;
  // every sim/scene message gets its SceneUpdate at the same log time
  const CopyCount n = copy_recording(r, w, [&](const record::Message& m) {
    if (m.topic != graph::kSceneState || !state.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) return;
    converter.convert(state, update);
    w.write(channel, ++scenes, m.log_time_ns, m.publish_time_ns, update.SerializeAsString());
  });
  w.close();
  std::printf("%llu messages copied, %u scene updates on %s -> %s\n", static_cast<unsigned long long>(n.messages), scenes, foxglove::kSceneTopic, out.c_str());
  for (const auto& d : r.damage()) std::fprintf(stderr, "enact export: %s: %s\n", r.path().c_str(), d.c_str());
  return 0;
}

}  // namespace enact::cli
