#pragma once
// Loading a scene from YAML (format: docs/scenes-and-models.md, "Scene files"). Every error names the
// file, the line and the fix, and is thrown as config::Error before anything runs.
#include <string>

#include "core/physics/model.h"

namespace enact::physics {

Model load_scene(const std::string& path);

// names of the exploratory body's masses: "<body>" is the proxy point (the centre),
// "<body>/r<row>c<col>" a grid mass
std::string grid_point_name(const std::string& body, int row, int col);

}  // namespace enact::physics
