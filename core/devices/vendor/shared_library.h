#pragma once
// A vendor's shared library opened at run time (dlopen), so enact builds and runs on machines
// without it: the library is looked for only when a device that needs it is configured, and
// its absence is a config::Error that says which file is missing and how to install or name it.
#include <string>

namespace enact::devices::vendor {

class SharedLibrary {
 public:
  SharedLibrary() = default;
  // dlopen `path` (a file name is searched on the loader's path, LD_LIBRARY_PATH included);
  // throws config::Error "DEVICE: cannot load PATH (dlerror)\n  fix: FIX"
  SharedLibrary(const std::string& path, const char* device, const std::string& fix);
  ~SharedLibrary();
  SharedLibrary(SharedLibrary&& other) noexcept;
  SharedLibrary& operator=(SharedLibrary&& other) noexcept;
  SharedLibrary(const SharedLibrary&) = delete;
  SharedLibrary& operator=(const SharedLibrary&) = delete;

  bool loaded() const { return handle_ != nullptr; }
  const std::string& path() const { return path_; }

  // the function `name` as a pointer of type F; throws config::Error naming the function and
  // the library when it is not exported (an SDK too old or not the vendor's library)
  template <class F>
  void bind(const char* name, F& out) const {
    out = reinterpret_cast<F>(address(name));
  }

 private:
  void* address(const char* name) const;

  void* handle_ = nullptr;
  std::string path_;
  const char* device_ = "";
};

// whether `path` can be loaded; the loader's message when not (for `enact devices`)
bool loadable(const std::string& path, std::string& why);

}  // namespace enact::devices::vendor
