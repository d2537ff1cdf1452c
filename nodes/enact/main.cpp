// enact: the command line of the enact haptics framework.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "core/config/suggest.h"
#include "core/config/yaml.h"
#include "nodes/enact/commands.h"

namespace {

constexpr const char* kUsage = R"(enact - integrated tactile + force-feedback haptics

usage: enact <command> [options]      (enact <command> --help for its options)

commands:
  check SCENE       load and validate a scene, print its stability table
  simulate SCENE    offline, deterministic run of a device path through the simulator
  path SCENE        write the built-in scripted hand path of a scene as CSV
  bench physics     integrator speed against error, bridge step cost
  bench loop        the real-time loop and the bus against the machine's floor
  bench record      MCAP writer throughput against raw writes; the logger's headroom
  launch FILE       run a graph of nodes from a YAML launch file
  graph list        the running graphs of this user (name, attach endpoint, pid, launch file)
  topic list|echo|hz|info|bw|pub  look at a running graph, send on its inbound topics
  node list|info    the nodes of a running graph: state, rate, topics, parameters
  record            keep a running graph's messages in an MCAP file
  info FILE         what a recording holds (topics, rates, gaps, metadata, damage)
  play FILE         republish a recording with its timing, as if live
  export FILE       one topic of a recording as CSV
  recover FILE      rebuild a complete recording from a damaged or unclosed one
  resim FILE        rerun a recording's device states through the simulator, compare
  devices           the supported USB devices on this machine (Novint Falcon, Metec cells)
  param set NAME VALUE  change a parameter of a running graph (answered: applied or refused)
  foxglove          serve a running graph to Foxglove (WebSocket): topics, schemas, the 3D scene
  doctor            is this machine ready for real-time haptics? one line per check, with the fix
  keys new|show     CURVE keys for remote access (graphs launched with --access)
  experiment FILE   run an experiment's trials (virtual subjects or people), resumable
  metrics FILE      a trial's metrics recomputed from its recording

Files: scenes and computer models are YAML, paths are CSV (docs/scenes-and-models.md).
)";

// the commands, by name
struct Command {
  const char* name;
  int (*run)(int, char**);
};
constexpr Command kCommands[] = {
    {"check", enact::cli::check},
    {"simulate", enact::cli::simulate},
    {"path", enact::cli::path},
    {"bench", enact::cli::bench},
    {"launch", enact::cli::launch},
    {"graph", enact::cli::graph_list},
    {"topic", enact::cli::topic},
    {"record", enact::cli::record},
    {"info", enact::cli::info},
    {"play", enact::cli::play},
    {"export", enact::cli::export_csv},
    {"recover", enact::cli::recover},
    {"resim", enact::cli::resim},
    {"devices", enact::cli::devices},
    {"param", enact::cli::param},
    {"foxglove", enact::cli::foxglove_bridge},
    {"doctor", enact::cli::doctor},
    {"node", enact::cli::node},
    {"keys", enact::cli::keys},
    {"experiment", enact::cli::experiment_run},
    {"metrics", enact::cli::metrics},
};

// " (did you mean X?)" for a misspelled command
std::string closest_command(const std::string& name) {
  std::vector<std::string> names;
  for (const Command& c : kCommands) names.emplace_back(c.name);
  return enact::config::did_you_mean(name, names);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "help")) {
    std::fputs(kUsage, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  if (!std::strcmp(argv[1], "--version")) {
    std::puts("enact 0.1.0");
    return 0;
  }
  const std::string command = argv[1];
  try {
    for (const Command& c : kCommands) {
      if (command == c.name) return c.run(argc, argv);
    }
    std::fprintf(stderr, "enact: unknown command '%s'%s\n\n%s", command.c_str(), closest_command(command).c_str(), kUsage);
    return 2;
  } catch (const enact::cli::UsageError& e) {
    std::fprintf(stderr, "enact %s: %s\n  (enact %s --help lists the options)\n", command.c_str(), e.what(), command.c_str());
    return 2;
  } catch (const enact::config::Error& e) {
    std::fprintf(stderr, "enact %s: error: %s\n", command.c_str(), e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "enact %s: error: %s\n", command.c_str(), e.what());
    return 1;
  }
}
