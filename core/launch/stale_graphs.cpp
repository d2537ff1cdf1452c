#include "core/launch/stale_graphs.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>

namespace enact::launch {
namespace {

// whether `folder` has a launcher.pid naming a process that is gone
bool launcher_gone(const std::filesystem::path& folder) {
  std::ifstream in(folder / kLauncherPidFile);
  long pid = 0;
  if (!(in >> pid) || pid <= 0) return false;
  return kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

}  // namespace

void mark_graph_folder(const std::string& graph_dir) {
  std::ofstream(std::filesystem::path(graph_dir) / kLauncherPidFile) << getpid() << "\n";
}

int remove_stale_graph_folders(const std::string& parent, const std::string& prefix) {
  std::error_code ec;
  int removed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(parent, ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(prefix) || !entry.is_directory(ec) || !launcher_gone(entry.path())) continue;
    removed += std::filesystem::remove_all(entry.path(), ec) > 0 ? 1 : 0;
  }
  return removed;
}

}  // namespace enact::launch
