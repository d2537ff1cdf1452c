#pragma once
// The latest value of a trivially copyable T, from one writer thread to any reader threads,
// without locks (a sequence lock): the writer never waits; a reader retries while a write is
// under way and always gets a whole value, never a mix of two. The value is held as relaxed
// atomic words, so the copy is free of data races. Allocates nothing; never blocks the
// writer. Used between a backend's I/O thread and the real-time loop.
#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace enact::devices::usb {

template <class T>
class Latest {
  static_assert(std::is_trivially_copyable_v<T>, "Latest<T> copies T as bytes");
  static constexpr std::size_t kWords = (sizeof(T) + sizeof(std::uint64_t) - 1) / sizeof(std::uint64_t);

 public:
  explicit Latest(const T& initial = T{}) { store(initial); }

  // the writer (one thread only)
  void store(const T& value) noexcept {
    std::array<std::uint64_t, kWords> words{};
    std::memcpy(words.data(), &value, sizeof(T));
    const std::uint64_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);  // odd: a write is under way
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(words[i], std::memory_order_relaxed);
    seq_.store(s + 2, std::memory_order_release);
  }

  // any reader
  T load() const noexcept {
    std::array<std::uint64_t, kWords> words{};
    while (true) {
      const std::uint64_t before = seq_.load(std::memory_order_acquire);
      if (before & 1u) continue;
      for (std::size_t i = 0; i < kWords; ++i) words[i] = words_[i].load(std::memory_order_relaxed);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == before) break;
    }
    T out;
    std::memcpy(static_cast<void*>(&out), words.data(), sizeof(T));
    return out;
  }

  // how many values were stored (changes with every store)
  std::uint64_t version() const noexcept { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  std::atomic<std::uint64_t> seq_{0};
  std::array<std::atomic<std::uint64_t>, kWords> words_{};
};

}  // namespace enact::devices::usb
