#pragma once
// The files a live graph keeps in its GraphInfo (kept_files.h: a recording keeps the same as
// attachments), read by the viewer and the Foxglove bridge alike.
#include <optional>
#include <string_view>

#include "core/graph/kept_files.h"
#include "msgs/graph.pb.h"

namespace enact::graph {

// the scene a graph names among its GraphInfo files, with the files it reads beside it
inline std::optional<NamedScene> scene_of(const msgs::GraphInfo& info) {
  return find_scene(info.files(), [](const msgs::GraphInfo::File& f) -> std::string_view { return f.name(); },
                    [](const msgs::GraphInfo::File& f) -> std::string_view { return f.data(); });
}

}  // namespace enact::graph
