#include <dlfcn.h>

#include <filesystem>
#include <map>
#include <set>

#include "core/config/share.h"
#include "core/config/yaml.h"
#include "core/node/loop_component.h"
#include "core/params/node_params.h"
#include "core/node/replay_stages.h"

namespace enact::node {

namespace {

struct Loaded {
  std::set<std::string> libraries;  // canonical paths
  std::map<std::string, LoopPlugin> plugins;
};
Loaded& loaded() {
  static Loaded l;
  return l;
}

[[noreturn]] void refuse(const std::string& path, const std::string& what, const std::string& fix) {
  throw config::Error(path + ": " + what + "\n  fix: " + fix);
}

}  // namespace

void load_plugin_library(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) refuse(path, "there is no plugin library here", "build it (" + config::shipped("docs/components.md") + "), or correct the path");
  const std::string canonical = std::filesystem::canonical(path, ec).string();
  if (!loaded().libraries.insert(canonical).second) return;
  // never closed: its stages' code runs until the process ends
  void* lib = dlopen(canonical.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    const char* why = dlerror();
    refuse(path, std::string("cannot load the plugin library: ") + (why ? why : "unknown reason"),
           "build it against this enact (an undefined symbol: it uses a function this program does not hold; a wrong ELF class: built for another machine)");
  }
  using Abi = int (*)();
  using Register = void (*)(PluginRegistry&);
  const auto abi = reinterpret_cast<Abi>(dlsym(lib, "enact_plugin_abi"));
  const auto add = reinterpret_cast<Register>(dlsym(lib, "enact_register_plugins"));
  if (!abi || !add) {
    refuse(path, "is not an enact plugin library (it exports no enact_plugin_abi or enact_register_plugins)",
           "export both as extern \"C\" (" + config::shipped("core/node/loop_component.h") + ", " + config::shipped("examples/plugins/guide_spring.cpp") + ")");
  }
  if (abi() != kPluginAbi) {
    refuse(path, "was built against plugin ABI " + std::to_string(abi()) + ", this enact has " + std::to_string(kPluginAbi),
           "rebuild it against this enact's " + config::shipped("core/node/loop_component.h"));
  }
  PluginRegistry registry;
  add(registry);
  if (registry.plugins.empty()) refuse(path, "registers no stage", "call r.add(...) in its enact_register_plugins");
  for (const LoopPlugin& p : registry.plugins) {
    if (!p.plugin || !p.what || !p.table || !p.make) refuse(path, "registers a stage with a field left empty", "give plugin, what, table and make");
    if (!graph::add_component_kind({p.plugin, graph::ComponentRole::stage, p.what, p.table, false})) {
      refuse(path, std::string("registers a stage named '") + p.plugin + "', a name a component plugin already has", "give the stage a name of its own");
    }
    loaded().plugins.emplace(p.plugin, p);
  }
}

std::unique_ptr<LoopComponent> make_stage(const std::string& plugin, const graph::Params& params) {
  const auto it = loaded().plugins.find(plugin);
  if (it == loaded().plugins.end()) return nullptr;
  std::unique_ptr<LoopComponent> stage = it->second.make(params);
  if (!stage) throw config::Error("plugin '" + plugin + "' made no stage\n  fix: its make() must return the stage, or throw why it cannot");
  return stage;
}

graph::StageStep replay_stages(const std::vector<graph::RecordedStage>& recorded, const std::vector<std::string>& libraries) {
  for (const std::string& library : libraries) load_plugin_library(library);
  // deactivated when the replay lets go of them
  struct Stages {
    std::vector<std::unique_ptr<LoopComponent>> list;
    ~Stages() {
      for (auto& stage : list) stage->deactivate();
    }
  };
  auto stages = std::make_shared<Stages>();
  for (const graph::RecordedStage& r : recorded) {
    if (!loaded().plugins.contains(r.plugin)) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(r.library, ec)) {
        refuse(r.library, "there is no plugin library here, and the recorded loop's stage '" + r.name + "' (plugin " + r.plugin + ") came from it",
               "give the library where it is now: --library PATH");
      }
      load_plugin_library(r.library);
    }
    graph::Params p(r.name);
    for (const auto& [name, value] : r.params) p.set(name, value);
    p.declare(*graph::component_table(r.plugin));
    std::unique_ptr<LoopComponent> stage = make_stage(r.plugin, p);
    if (!stage) refuse(r.library, "registers no plugin '" + r.plugin + "', the recorded loop's stage '" + r.name + "'", "give the library that holds it: --library PATH");
    p.refuse_unknown();
    stages->list.push_back(std::move(stage));
  }
  for (auto& stage : stages->list) stage->activate();
  return [stages](std::int64_t time_ns, std::int64_t model_time_ns, const devices::ForceSample& sample, sim::StepOutput& step) {
    Tick tick{time_ns, model_time_ns, &sample, &step};
    for (auto& stage : stages->list) stage->step(tick);
  };
}

}  // namespace enact::node
