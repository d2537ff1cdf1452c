#pragma once
// The files a graph or a recording keeps by name: a graph's GraphInfo files and a recording's
// attachments, under the parameter that names them ("rt.sim.scene"). A file read beside
// another (a scene's meshes and height maps) is kept as "<its name>/<its path relative to
// it>" (session/launch_info.cpp); what reads them puts them back beside it
// (TempFolder::put). Generic over the kind of kept file: name_of and data_of read one.
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace enact::graph {

// the files kept beside one: each path relative to it, and its data
using FilesBeside = std::vector<std::pair<std::string, std::string>>;

// the files kept beside the one kept as `name`
template <class Files, class NameOf, class DataOf>
FilesBeside files_beside(const Files& kept, std::string_view name, NameOf name_of, DataOf data_of) {
  FilesBeside out;
  for (const auto& f : kept) {
    const std::string_view n = name_of(f);
    if (n.size() > name.size() + 1 && n.starts_with(name) && n[name.size()] == '/') out.emplace_back(std::string(n.substr(name.size() + 1)), std::string(data_of(f)));
  }
  return out;
}

// "rt.sim.scene" -> "sim", "sim.scene" -> "sim"; "" for a key that names no scene
inline std::string sim_of_scene_key(std::string_view key) {
  constexpr std::string_view kScene = ".scene";
  if (key.size() <= kScene.size() || !key.ends_with(kScene)) return "";
  const std::string_view prefix = key.substr(0, key.size() - kScene.size());
  return std::string(prefix.substr(prefix.rfind('.') + 1));
}

// the scene a graph's simulator runs, as the graph names it: under the parameter
// "<node>.scene" or "<container>.<component>.scene"
struct NamedScene {
  std::string sim;      // the simulator's node or component name (its parameters' prefix)
  std::string data;     // the scene file's text
  FilesBeside beside;   // the files it reads beside it (height maps, meshes)
  bool operator==(const NamedScene&) const = default;
};

// the first scene among the kept files, with the files beside it; none if none names one
template <class Files, class NameOf, class DataOf>
std::optional<NamedScene> find_scene(const Files& kept, NameOf name_of, DataOf data_of) {
  for (const auto& f : kept) {
    const std::string_view key = name_of(f);
    if (std::string sim = sim_of_scene_key(key); !sim.empty()) return NamedScene{std::move(sim), std::string(data_of(f)), files_beside(kept, key, name_of, data_of)};
  }
  return std::nullopt;
}

}  // namespace enact::graph
