#include "tests/support/file_guard.h"

#include <dlfcn.h>
#include <fcntl.h>

#include <atomic>
#include <cstdarg>
#include <cstdio>

#include "core/rt/rt_section.h"

namespace {

thread_local bool counting = false;
thread_local std::size_t count = 0;
std::atomic<std::size_t> everyone{0};
std::atomic<std::size_t> in_sections{0};

void note() {
  everyone.fetch_add(1, std::memory_order_relaxed);
  if (counting) ++count;
  if (enact::rt::in_rt_section) in_sections.fetch_add(1, std::memory_order_relaxed);
}

// the next definition of `name` after this program's (the C library's, or a sanitizer's)
template <class Fn>
Fn next(const char* name) {
  return reinterpret_cast<Fn>(dlsym(RTLD_NEXT, name));
}

// counts one open, then makes it with the next definition of `name`
template <class Fn, class... Args>
auto counted(const char* name, Args... args) {
  note();
  return next<Fn>(name)(args...);
}

using OpenFn = int (*)(const char*, int, ...);
using OpenAtFn = int (*)(int, const char*, int, ...);
using FopenFn = FILE* (*)(const char*, const char*);

}  // namespace

// open's optional third argument (the mode), present when a file may be created
#define ENACT_OPEN_MODE(flags)          \
  mode_t mode = 0;                      \
  if ((flags) & (O_CREAT | O_TMPFILE)) { \
    va_list args;                       \
    va_start(args, flags);              \
    mode = va_arg(args, int);           \
    va_end(args);                       \
  }

extern "C" {

int open(const char* path, int flags, ...) {
  ENACT_OPEN_MODE(flags)
  return counted<OpenFn>("open", path, flags, mode);
}

int open64(const char* path, int flags, ...) {
  ENACT_OPEN_MODE(flags)
  return counted<OpenFn>("open64", path, flags, mode);
}

int openat(int dir, const char* path, int flags, ...) {
  ENACT_OPEN_MODE(flags)
  return counted<OpenAtFn>("openat", dir, path, flags, mode);
}

int openat64(int dir, const char* path, int flags, ...) {
  ENACT_OPEN_MODE(flags)
  return counted<OpenAtFn>("openat64", dir, path, flags, mode);
}

FILE* fopen(const char* path, const char* mode) { return counted<FopenFn>("fopen", path, mode); }

FILE* fopen64(const char* path, const char* mode) { return counted<FopenFn>("fopen64", path, mode); }

}  // extern "C"

namespace enact::test {

FileGuard::FileGuard() : start_(count), was_counting_(counting) { counting = true; }

FileGuard::~FileGuard() { counting = was_counting_; }

std::size_t FileGuard::opens() const { return count - start_; }

std::size_t FileGuard::opens_by_any_thread() { return everyone.load(); }

std::size_t FileGuard::opens_in_rt_sections() { return in_sections.load(); }

}  // namespace enact::test
