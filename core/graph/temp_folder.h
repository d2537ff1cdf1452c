#pragma once
// A fresh temporary folder, removed with everything in it when destroyed: for files taken
// out of a graph's GraphInfo or a recording (a scene, a computer model) so that the loaders,
// which read paths, can read them; for a graph's ipc sockets; for benchmark files.
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "core/graph/kept_files.h"

namespace enact::graph {

class TempFolder {
 public:
  // a fresh folder `prefix` + 6 random characters (default: under the system's temporary
  // directory); throws std::runtime_error
  explicit TempFolder(std::string prefix = (std::filesystem::temp_directory_path() / "enact-files-").string()) {
    std::string pattern = prefix + "XXXXXX";
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary folder " + pattern);
    path_ = pattern;
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  const std::string& path() const { return path_; }

  // writes `data` as `name` (with the extension of `like`); returns its path
  std::string put(const std::string& name, const std::string& like, const std::string& data) const {
    const std::string p = path_ + "/" + name + std::filesystem::path(like).extension().string();
    std::ofstream(p, std::ios::binary) << data;
    return p;
  }

  // put(name, like, data), and each file kept beside it at its path relative to it (put_at;
  // one whose path would leave the folder is left out: its loader says what is missing)
  std::string put(const std::string& name, const std::string& like, const std::string& data, const FilesBeside& beside) const {
    for (const auto& [relative, file] : beside) put_at(relative, file);
    return put(name, like, data);
  }

  // writes `data` at `relative` (a path inside the folder, its folders made); returns its
  // path, or "" for a path that would leave the folder (absolute, or through "..")
  std::string put_at(const std::string& relative, const std::string& data) const {
    const std::filesystem::path inside = std::filesystem::path(relative).lexically_normal();
    if (inside.empty() || inside.is_absolute() || *inside.begin() == "..") return "";
    const std::filesystem::path p = std::filesystem::path(path_) / inside;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << data;
    return p.string();
  }

 private:
  std::string path_;
};

}  // namespace enact::graph
