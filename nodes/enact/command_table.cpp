#include "nodes/enact/command_table.h"

#include <cstdio>
#include <cstring>
#include <exception>
#include <vector>

#include "core/config/share.h"
#include "core/config/suggest.h"
#include "core/config/yaml.h"
#include "core/params/node_params.h"
#include "core/params/param_table.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

// the commands: one row a usage line (a command with several forms has a row each)
struct Command {
  const char* name;      // what follows `enact`
  const char* synopsis;  // its form in the usage
  const char* text;      // what it does
  int (*run)(int, char**);
};
constexpr Command kCommands[] = {
    {"check", "check SCENE", "load and validate a scene, print its stability table", check},
    {"simulate", "simulate SCENE", "offline, deterministic run of a device path through the simulator", simulate},
    {"path", "path SCENE", "write the built-in scripted hand path of a scene as CSV", path},
    {"bench", "bench physics", "integrator speed against error, bridge step cost", run_bench},
    {"bench", "bench loop", "the real-time loop and the bus against the machine's floor", run_bench},
    {"bench", "bench record", "MCAP writer throughput against raw writes; the logger's headroom", run_bench},
    {"launch", "launch FILE", "run a graph of nodes from a YAML launch file", launch},
    {"graph", "graph list", "the running graphs of this user (name, attach endpoint, pid, launch file)", graph_list},
    {"topic", "topic list|echo|hz|info|bw|pub", "look at a running graph, send on its inbound topics", topic},
    {"node", "node list|info", "the nodes of a running graph: state, rate, topics, parameters", node},
    {"record", "record", "keep a running graph's messages in an MCAP file", record},
    {"info", "info FILE", "what a recording holds (topics, rates, gaps, metadata, damage)", info},
    {"play", "play FILE", "republish a recording with its timing, as if live", play},
    {"export", "export FILE", "one topic of a recording as CSV", export_csv},
    {"recover", "recover FILE", "rebuild a complete recording from a damaged or unclosed one", recover},
    {"resim", "resim FILE", "rerun a recording's device states through the simulator, compare", resim},
    {"devices", "devices", "the supported USB devices on this machine (Novint Falcon, Metec cells)", devices},
    {"param", "param set NAME VALUE", "change a parameter of a running graph (answered: applied or refused)", param},
    {"param", "param list|get|dump|load", "a running graph's parameters: values in force, ranges; as YAML and back", param},
    {"foxglove", "foxglove", "serve a running graph to Foxglove (WebSocket): topics, schemas, the 3D scene", foxglove_bridge},
    {"doctor", "doctor", "is this machine ready for real-time haptics? one line per check, with the fix", doctor},
    {"keys", "keys new|show", "CURVE keys for remote access (graphs launched with --access)", keys},
    {"experiment", "experiment FILE", "run an experiment's trials (virtual subjects or people), resumable", experiment_run},
    {"sweep", "sweep FILE", "an experiment over a grid of parameters x replicates (here, Slurm, Dask), resumable", sweep_run},
    {"metrics", "metrics FILE", "a trial's metrics recomputed from its recording", metrics},
    {"share", "share [--all] [FILE...]", "where enact's shipped files are (launch files, scenes, scripts, docs): paths that work from any folder", share},
    {"help", "help [--markdown]", "this list; --markdown: the command and parameter reference (docs/cli.md)", help},
};

constexpr const char* kHead = "enact - integrated tactile + force-feedback haptics\n\nusage: enact <command> [options]      (enact <command> --help for its options)\n\ncommands:\n";
// where the docs the commands' --help name (docs/NAME.md) and the shipped files are: installed,
// or the source tree of a build
std::string foot() {
  std::string out = "\nFiles: scenes and computer models are YAML, paths are CSV (" + config::shipped("docs/scenes-and-models.md") + ").\n";
  const std::vector<config::ShareRoot> roots = config::share_roots();
  if (!roots.empty()) out += "Docs (docs/NAME.md in --help): " + roots.front().docs + "; launch files, scenes, scripts: " + roots.front().data + " (enact share)\n";
  return out;
}

// the nodes of a launch file, whose parameters the reference lists
constexpr const char* kNodes[] = {"enact-sim", "enact-ffd", "enact-tactile", "enact-rt", "enact-logger", "enact-foxglove"};

// " (did you mean X?)" for a misspelled command
std::string closest_command(const std::string& name) {
  std::vector<std::string> names;
  for (const Command& c : kCommands) {
    if (names.empty() || names.back() != c.name) names.emplace_back(c.name);
  }
  return config::did_you_mean(name, names);
}

// `text` in a Markdown table cell ('|' escaped)
std::string cell(std::string text) {
  for (std::size_t p = 0; (p = text.find('|', p)) != std::string::npos; p += 2) text.replace(p, 1, "\\|");
  return text;
}

// a parameter table as Markdown rows
std::string markdown_rows(const graph::ParamTable& table, const std::string& prefix) {
  std::string out = "| parameter | type | default | values | live | what it is |\n|---|---|---|---|---|---|\n";
  for (const graph::ParamSpec& s : table) {
    const std::string fallback = !s.at_start ? "(live only)" : s.required ? "(required)" : s.fallback.empty() ? "" : "`" + s.fallback + "`";
    out += "| `" + prefix + s.name + "` | " + graph::type_name(s.type) + " | " + cell(fallback) + " | " + cell(graph::range_text(s)) + " | " + (s.live ? "yes" : "") +
           " | " + cell(s.doc) + " |\n";
  }
  return out;
}

}  // namespace

std::string usage() {
  std::string out = kHead;
  for (const Command& c : kCommands) {
    const std::string syn = c.synopsis;
    out += "  " + syn + std::string(syn.size() + 2 < 18 ? 18 - syn.size() : 2, ' ') + c.text + "\n";
  }
  return out + foot();
}

std::string reference_markdown() {
  std::string out =
      "# Command and parameter reference\n\nGenerated from the code by `enact help --markdown` (a test fails when this file and the code\n"
      "differ: regenerate it with `enact help --markdown > docs/cli.md`). Each command's options: `enact COMMAND --help`.\n\n"
      "## Commands\n\n| command | what it does |\n|---|---|\n";
  for (const Command& c : kCommands) out += "| `enact " + cell(c.synopsis) + "` | " + cell(c.text) + " |\n";
  out += "\n## Node parameters\n\nGiven in a launch file (`param:`) or as `--param NAME=VALUE`; live ones also with `enact param set`.\n";
  for (const char* node : kNodes) out += std::string("\n### ") + node + "\n\n" + markdown_rows(*graph::node_table(node), "");
  out += "\n## Components of enact-rt\n\nGiven as `--param COMPONENT.NAME=VALUE` (e.g. `sim.scene`).\n";
  for (const graph::ComponentKind& k : graph::component_kinds()) out += std::string("\n### ") + k.plugin + "\n\n" + markdown_rows(k.table(), std::string(k.plugin) + ".");
  return out;
}

int help(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {}, {"markdown"});
  std::fputs(a.flag("markdown") ? reference_markdown().c_str() : usage().c_str(), stdout);
  return 0;
}

int run_command(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help")) {
    std::fputs(usage().c_str(), argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  if (!std::strcmp(argv[1], "--version")) {
    std::printf("%s (git %s)\n", version(), git_commit());
    return 0;
  }
  const std::string command = argv[1];
  try {
    for (const Command& c : kCommands) {
      if (command == c.name) return c.run(argc, argv);
    }
    std::fprintf(stderr, "enact: unknown command '%s'%s\n\n%s", command.c_str(), closest_command(command).c_str(), usage().c_str());
    return 2;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "enact %s: %s\n  (enact %s --help lists the options)\n", command.c_str(), e.what(), command.c_str());
    return 2;
  } catch (const config::Error& e) {
    std::fprintf(stderr, "enact %s: error: %s\n", command.c_str(), e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "enact %s: error: %s\n", command.c_str(), e.what());
    return 1;
  }
}

}  // namespace enact::cli
