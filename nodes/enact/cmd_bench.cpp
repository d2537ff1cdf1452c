// enact bench: the benchmarks are an executable of their own (nodes/enact-bench: Google
// Benchmark and the loop's measuring arms stay out of the command line's link); this runs it
// with the same arguments
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "core/config/yaml.h"
#include "core/launch/launch_file.h"
#include "nodes/enact/commands.h"

namespace enact::cli {

int run_bench(int argc, char** argv) {
  std::string exe = launch::default_resolver()("enact-bench");
  if (exe.empty()) throw config::Error("enact-bench is neither beside enact nor on PATH\n  fix: build it (cmake --build build --target enact-bench), or install it beside enact");
  std::vector<char*> args(argv, argv + argc);
  args[0] = exe.data();
  args.push_back(nullptr);
  execv(exe.c_str(), args.data());
  throw config::Error("cannot run " + exe + ": " + std::strerror(errno));
}

}  // namespace enact::cli
