#pragma once
// Folders of graphs whose launcher died without cleaning up (SIGKILL, a power cut): each
// launcher writes its pid into its graph's folder, and the next launch removes every folder
// whose launcher is gone.
#include <string>

namespace enact::launch {

// the file in a graph's folder that names its launcher's pid
inline constexpr const char* kLauncherPidFile = "launcher.pid";

// writes this process's pid into `graph_dir`/launcher.pid
void mark_graph_folder(const std::string& graph_dir);

// removes every folder `parent`/`prefix`* whose launcher.pid names a process that no longer
// exists (folders without that file are left alone); returns how many it removed
int remove_stale_graph_folders(const std::string& parent, const std::string& prefix);

}  // namespace enact::launch
