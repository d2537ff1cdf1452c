#include "tests/support/alloc_guard.h"

#include <atomic>
#include <cerrno>
#include <cstdlib>

#include "core/rt/rt_section.h"

namespace {

thread_local bool counting = false;
thread_local std::size_t count = 0;
std::atomic<std::size_t> in_sections{0};

void note() {
  if (counting) ++count;
  if (enact::rt::in_rt_section) in_sections.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

// AddressSanitizer's allocator serves every allocation of a sanitized build (CI's second
// build): count through its hook, since replacing malloc would mix the two allocators
#if defined(__SANITIZE_ADDRESS__)
#define ENACT_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ENACT_ASAN 1
#endif
#endif

#ifdef ENACT_ASAN
// the sanitizer runtime's (sanitizer/allocator_interface.h, which gcc does not install)
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*on_malloc)(const volatile void*, std::size_t),
                                                         void (*on_free)(const volatile void*));

namespace {

void on_malloc(const volatile void*, std::size_t) { note(); }
void on_free(const volatile void*) {}
[[maybe_unused]] const int hooks_installed = __sanitizer_install_malloc_and_free_hooks(on_malloc, on_free);

}  // namespace

#else
// glibc's own allocator entry points, under their internal names
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t n, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
void __libc_free(void* p);
}

extern "C" {

void* malloc(std::size_t size) {
  note();
  return __libc_malloc(size);
}

void* calloc(std::size_t n, std::size_t size) {
  note();
  return __libc_calloc(n, size);
}

void* realloc(void* p, std::size_t size) {
  note();
  return __libc_realloc(p, size);
}

void free(void* p) { __libc_free(p); }

void* aligned_alloc(std::size_t alignment, std::size_t size) {
  note();
  return __libc_memalign(alignment, size);
}

void* memalign(std::size_t alignment, std::size_t size) {
  note();
  return __libc_memalign(alignment, size);
}

int posix_memalign(void** out, std::size_t alignment, std::size_t size) {
  note();
  void* p = __libc_memalign(alignment, size);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}

}  // extern "C"
#endif

namespace enact::test {

AllocGuard::AllocGuard() : start_(count), was_counting_(counting) { counting = true; }

AllocGuard::~AllocGuard() { counting = was_counting_; }

std::size_t AllocGuard::allocations() const { return count - start_; }

std::size_t AllocGuard::in_rt_sections() { return in_sections.load(); }

}  // namespace enact::test
