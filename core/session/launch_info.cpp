#include "core/session/launch_info.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/config/share.h"
#include "core/params/node_params.h"
#include "core/physics/scene.h"
#include "core/rt/clock.h"

namespace enact::graph {
namespace {

const char* media_type(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".yaml" || ext == ".yml") return "application/yaml";
  if (ext == ".csv") return "text/csv";
  return "application/octet-stream";
}

}  // namespace

msgs::GraphInfo launch_info(const std::string& launch_path, const launch::LaunchDescription& graph) {
  msgs::GraphInfo info;
  info.set_launch_file(std::filesystem::absolute(launch_path).string());
  std::ifstream in(launch_path);
  std::stringstream text;
  text << in.rdbuf();
  info.set_launch_text(text.str());
  info.set_clock(rt::to_string(graph.clock));
  // a file kept as `name` (small ones only); false when there is none to keep
  auto keep = [&](const std::string& name, const std::string& path) {
    std::error_code ec;
    if (path.empty() || !std::filesystem::is_regular_file(path, ec) || std::filesystem::file_size(path, ec) > (1u << 20)) return false;
    std::ifstream f(path, std::ios::binary);
    std::stringstream data;
    data << f.rdbuf();
    auto& file = *info.add_files();
    file.set_name(name);
    file.set_path(std::filesystem::absolute(path).string());
    file.set_media_type(media_type(path));
    file.set_data(data.str());
    return true;
  };
  auto add = [&](const std::string& name, const std::string& given) {
    auto& p = *info.add_params();
    p.set_name(name);
    p.set_value(given);
    // a file as its node finds it: where the user stands, else enact's share (config/share.h)
    const std::string value = given.empty() ? given : config::locate(given).value_or(given);
    // a parameter naming a file: keep the file, and the files a scene reads beside it as
    // "<name>/<path relative to it>" (TempFolder::put puts them back: core/graph/kept_files.h)
    if (!keep(name, value) || !value.ends_with(".yaml")) return;
    for (const std::string& beside : physics::files_beside_scene(value)) keep(name + "/" + beside, (std::filesystem::path(value).parent_path() / beside).string());
  };
  bool ffd = false, sim = false, zeromq = false, colocated = false;
  for (const auto& n : graph.nodes) {
    for (const auto& p : n.params) add(n.name + "." + p.name, p.value);
    for (const auto& c : n.components) {
      for (const auto& p : c.params) add(n.name + "." + c.name + "." + p.name, p.value);
      auto& component = *info.add_components();
      component.set_node(n.name);
      component.set_name(c.name);
      component.set_plugin(c.plugin);
      if (!c.library.empty()) component.set_library(std::filesystem::absolute(c.library).string());
    }
    const std::string exe = std::filesystem::path(n.exec).filename().string();
    if (node_table(exe)) info.add_param_nodes(n.name);
    colocated = colocated || exe == "enact-rt";
    ffd = ffd || exe == "enact-ffd";
    sim = sim || exe == "enact-sim";
    for (const auto& p : n.params) zeromq = zeromq || (p.name == "loop_transport" && p.value == "zeromq");
  }
  info.set_loop_hop(colocated ? "co-located" : ffd && sim ? (zeromq ? "zeromq" : "local") : "");
  return info;
}

}  // namespace enact::graph
