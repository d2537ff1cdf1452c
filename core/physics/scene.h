#pragma once
// Loading a scene from YAML (format: docs/scenes-and-models.md, "Scene files"). Every error names the
// file, the line and the fix, and is thrown as config::Error before anything runs.
#include <string>
#include <vector>

#include "core/physics/model.h"

namespace enact::physics {

Model load_scene(const std::string& path);

// the files a scene's objects read (`file:` of a mesh or a height map), as written, when they
// lie in the scene's folder or below it (a relative path without ".."): what a recording keeps
// beside the scene so that it replays anywhere. Not a scene, or unreadable: none. Never throws.
std::vector<std::string> files_beside_scene(const std::string& path);

// names of the exploratory body's masses: "<body>" is the proxy point (the centre),
// "<body>/r<row>c<col>" a grid mass
std::string grid_point_name(const std::string& body, int row, int col);

}  // namespace enact::physics
