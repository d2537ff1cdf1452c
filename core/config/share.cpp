#include "core/config/share.h"

#include <algorithm>
#include <filesystem>

#include "core/config/yaml.h"

namespace enact::config {
namespace {

namespace fs = std::filesystem;

// the folder of the running executable ("" when /proc does not say)
fs::path executable_dir() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : self.parent_path();
}

// `inside` is `folder` or below it
bool below(const fs::path& inside, const fs::path& folder) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(inside, ec), b = fs::weakly_canonical(folder, ec);
  const auto [end, _] = std::mismatch(b.begin(), b.end(), a.begin(), a.end());
  return !b.empty() && end == b.end();
}

// the candidate of `path` under a root: docs/NAME in its docs folder, core/... in its headers,
// the rest in its data
fs::path under(const ShareRoot& root, const fs::path& path) {
  const auto first = path.begin();
  if (first != path.end() && *first == "docs") return fs::path(root.docs) / path.lexically_relative("docs");
  if (first != path.end() && *first == "core") return fs::path(root.headers) / path;
  return fs::path(root.data) / path;
}

// every place `path` is looked for, in order, with what each is
std::vector<std::pair<fs::path, std::string>> candidates(const std::string& path, const std::string& naming_file) {
  const fs::path p(path);
  if (p.is_absolute()) return {{p, ""}};
  std::vector<std::pair<fs::path, std::string>> out;
  if (naming_file.empty()) {
    out.emplace_back(fs::absolute(p), "the current directory");
  } else {
    out.emplace_back(fs::absolute(naming_file).parent_path() / p, "beside " + naming_file);
  }
  for (const ShareRoot& root : share_roots()) out.emplace_back(under(root, p), root.what);
  return out;
}

}  // namespace

std::vector<ShareRoot> share_roots() {
  std::vector<ShareRoot> roots;
  const fs::path self = executable_dir();
  if (self.empty()) return roots;
  std::error_code ec;
  const fs::path prefix = self.parent_path();
  if (fs::is_directory(prefix / kShareDir, ec)) {
    roots.push_back({(prefix / kShareDir).lexically_normal().string(), (prefix / kDocDir).lexically_normal().string(),
                     (prefix / kIncludeDir).lexically_normal().string(), "the installed share"});
  }
#if defined(ENACT_SOURCE_DIR) && defined(ENACT_BINARY_DIR)
  // an executable of the build this library was compiled for: its source tree
  if (below(self, ENACT_BINARY_DIR) && fs::is_directory(ENACT_SOURCE_DIR, ec)) {
    roots.push_back({ENACT_SOURCE_DIR, (fs::path(ENACT_SOURCE_DIR) / "docs").string(), ENACT_SOURCE_DIR, "the source tree of this build"});
  }
#endif
  return roots;
}

std::optional<std::string> locate(const std::string& path, const std::string& naming_file) {
  if (path.empty()) return std::nullopt;
  std::error_code ec;
  const auto places = candidates(path, naming_file);
  for (std::size_t i = 0; i < places.size(); ++i) {
    if (!fs::exists(places[i].first, ec)) continue;
    // where the user stands: as written (messages keep the user's words)
    return i == 0 && naming_file.empty() ? path : places[i].first.lexically_normal().string();
  }
  return std::nullopt;
}

std::string find_file(const std::string& path, const std::string& naming_file) {
  if (auto found = locate(path, naming_file)) return *found;
  std::string looked;
  for (const auto& [candidate, what] : candidates(path, naming_file)) {
    looked += "\n  looked in " + candidate.lexically_normal().string() + (what.empty() ? "" : " (" + what + ")");
  }
  const bool relative = fs::path(path).is_relative();
  throw Error(path + ": cannot open the file" + looked + "\n  fix: check the path" +
              (relative ? std::string(" (relative paths start from ") + (naming_file.empty() ? "the current directory" : "the file that names it") +
                              ", then enact's share: `enact share` prints it)"
                        : ""));
}

std::string shipped(const std::string& relative) { return locate(relative, "").value_or(relative); }

std::string share_dir() {
  const std::vector<ShareRoot> roots = share_roots();
  if (roots.empty()) {
    throw Error("$(share): this enact has no share folder (neither " + (executable_dir().parent_path() / kShareDir).string() +
                " nor a build's source tree)\n  fix: install enact (cmake --install build --prefix P), or run it from its build");
  }
  return roots.front().data;
}

}  // namespace enact::config
