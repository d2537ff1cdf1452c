#pragma once
// Where enact's shipped files are (launch files, scenes, hand paths, experiments, scripts,
// docs, the example plugin), as ROS 2's $(find-pkg-share) finds a package's: one lookup for
// every path a user gives or a file names.
//
// A path is taken as written (absolute, or relative to where the user stands), else beside the
// file that names it, else in enact's share: the installed one (<prefix>/share/enact, found from
// the running executable, <prefix>/bin/...) and, for an executable of a build, the source tree
// it was built from. Installed, `docs/NAME` is <prefix>/share/doc/enact/NAME and a header
// `core/...` is <prefix>/include/enact/core/... (what a plugin includes).
#include <optional>
#include <string>
#include <vector>

namespace enact::config {

// where an installed enact's data is, relative to the prefix (CMakeLists.txt installs it there)
inline constexpr const char* kShareDir = "share/enact";
inline constexpr const char* kDocDir = "share/doc/enact";
inline constexpr const char* kIncludeDir = "include/enact";

// one place enact's files may be: `data` holds launch/, scripts/, examples/, `docs` the docs,
// `headers` core/'s headers
struct ShareRoot {
  std::string data;
  std::string docs;
  std::string headers;
  const char* what;  // "the installed share", "the source tree (this is a build's enact)"
};

// the installed share beside the running executable, then the source tree when it runs from a
// build; each only when it is there
std::vector<ShareRoot> share_roots();

// where `path` is: as written (relative: from the current directory), or beside `naming_file`'s
// folder when one names it (then not from the current directory), else in the share roots.
// nullopt when none has it
std::optional<std::string> locate(const std::string& path, const std::string& naming_file = "");

// locate, or config::Error "PATH: cannot open the file" listing every place it looked and the fix
std::string find_file(const std::string& path, const std::string& naming_file = "");

// a shipped file (relative to the top of enact's tree: "scripts/power.py", "docs/cli.md") as a
// hint prints it: the path where it is, so the command works where the user stands; as given
// when no root has it
std::string shipped(const std::string& relative);

// the first share root's data folder ($(share) in launch and experiment files); config::Error
// when there is none (an executable neither installed nor of a build)
std::string share_dir();

}  // namespace enact::config
