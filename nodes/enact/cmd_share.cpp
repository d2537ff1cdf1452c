// enact share [FILE...]: where enact's shipped files are (as ROS 2's `ros2 pkg prefix` and
// $(find-pkg-share) say where a package's are): the one lookup of core/config/share.h.
#include <cstdio>

#include "core/config/share.h"
#include "core/config/yaml.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kShareHelp = R"help(usage: enact share [--all] [FILE...]

Where enact's shipped files are: the launch files, scenes, hand paths and experiments
(launch/...), the scripts (scripts/...), the example plugin (examples/plugins/...), the docs
(docs/...) and the headers a plugin includes (core/...). Without FILE: the share folder
($(share) in launch and experiment files); with --all, every place looked in, in order, one
line each. With FILE (named as in enact's tree, e.g. scripts/analyze.py): its path, one line
each, so that a command works from any folder:

  /usr/bin/python3 "$(enact share scripts/analyze.py)" results/quick/results.csv

A path a command is given (a scene, a launch file, an experiment, --arg scene=...) is looked
for where you stand (or beside the file that names it), then in these places. An installed
enact's are <prefix>/share/enact, <prefix>/share/doc/enact (docs/) and <prefix>/include/enact
(core/); a build's enact looks in the source tree it was built from. Exit 1 naming where it
looked when a FILE is in none of them.
)help";

}  // namespace

int share(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {}, {"all"});
  if (a.flag("help")) {
    std::fputs(kShareHelp, stdout);
    return 0;
  }
  if (a.flag("all")) {
    for (const config::ShareRoot& root : config::share_roots()) {
      std::printf("%s (docs: %s, headers: %s): %s\n", root.data.c_str(), root.docs.c_str(), root.headers.c_str(), root.what);
    }
    return 0;
  }
  if (a.positional.empty()) {
    std::printf("%s\n", config::share_dir().c_str());
    return 0;
  }
  for (const std::string& file : a.positional) {
    const std::string found = config::find_file(file);
    std::printf("%s\n", found.c_str());
  }
  return 0;
}

}  // namespace enact::cli
