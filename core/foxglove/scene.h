#pragma once
// The scene for Foxglove's 3D panel: a graph's SceneState (sim/scene) turned into a
// foxglove.SceneUpdate (msgs/foxglove/scene_update.proto) with the scene file the simulator
// runs. One converter for the live bridge (enact foxglove) and for recordings (enact export
// --foxglove). Every update is whole (bridge, floor, body grid, force arrow), so a client
// that joins late or seeks in a recording sees the full scene from any one message.
#include <optional>
#include <string>

#include "core/graph/graph_files.h"
#include "core/physics/model.h"
#include "msgs/foxglove/scene_update.pb.h"
#include "msgs/graph.pb.h"
#include "msgs/scene_state.pb.h"

namespace enact::foxglove {

// the topic of the scene, next to the graph's own topics
inline constexpr const char* kSceneTopic = "foxglove/scene";
// the frame every entity is drawn in: the scene's own (m, z up)
inline constexpr const char* kSceneFrame = "scene";
// the force arrow's length per newton, m/N
inline constexpr double kArrowLength_m_per_n = 0.004;

class SceneConverter {
 public:
  // from a loaded scene (its boxes, floor and body grid)
  explicit SceneConverter(const physics::Model& model);

  // the update for one SceneState: bridge boxes, floor, the grid's masses coloured by
  // contact (red in contact, grey not), the resultant force as an arrow from the body
  void convert(const msgs::SceneState& state, ::foxglove::SceneUpdate& out) const;

 private:
  physics::Model model_;
  ::foxglove::SceneEntity fixed_;  // bridge and floor, the same in every update
};

// the scene named by a GraphInfo (a parameter "<sim>.scene" among its files), with the files
// it reads beside it, if any
using graph::scene_of;

// a converter for a scene kept by a graph or a recording (loaded through a temporary folder,
// as the loaders read paths); throws config::Error for a scene that does not load
SceneConverter converter_for(const graph::NamedScene& scene);

}  // namespace enact::foxglove
