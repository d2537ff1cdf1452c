#pragma once
// A lock-free single-producer single-consumer ring: the real-time loop pushes, a non-real-time
// thread pops (DESIGN.md: observers are fed from a lock-free queue). Never blocks, never
// allocates (the storage is a member), never throws. Exactly one thread may push and exactly
// one thread may pop at a time.
#include <array>
#include <atomic>
#include <cstddef>
#include <type_traits>

namespace enact::rt {

template <class T, std::size_t Capacity>
class SpscQueue {
  static_assert(Capacity > 0 && (Capacity & (Capacity - 1)) == 0, "SpscQueue: Capacity must be a power of two");
  static_assert(std::is_trivially_copyable_v<T>, "SpscQueue: T must be trivially copyable");

 public:
  // producer: append a copy of `item`; false when full (the caller counts a drop)
  bool try_push(const T& item) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_cache_ == Capacity) {
      // looks full: see how far the consumer has got
      head_cache_ = head_.load(std::memory_order_acquire);
      if (tail - head_cache_ == Capacity) return false;
    }
    slots_[tail & kMask] = item;
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  // consumer: take the oldest item into `out`; false when empty
  bool try_pop(T& out) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_cache_) {
      // looks empty: see how far the producer has got
      tail_cache_ = tail_.load(std::memory_order_acquire);
      if (head == tail_cache_) return false;
    }
    out = slots_[head & kMask];
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  // consumer: take the oldest items into `out`, as many as it holds at most; returns how many
  template <std::size_t N>
  std::size_t take(std::array<T, N>& out) {
    std::size_t n = 0;
    while (n < N && try_pop(out[n])) ++n;
    return n;
  }

  // the number of items, exact when neither side is running (from either thread)
  std::size_t size_approx() const {
    // head first: the tail read after it is never behind it
    const std::size_t head = head_.load(std::memory_order_acquire);
    const std::size_t tail = tail_.load(std::memory_order_acquire);
    return tail - head;
  }

  static constexpr std::size_t capacity() { return Capacity; }

 private:
  static constexpr std::size_t kMask = Capacity - 1;
  static constexpr std::size_t kCacheLine = 64;

  // indices count up forever (wrapping is harmless: only differences and low bits are used);
  // each side's index and its cached copy of the other side's share a cache line
  alignas(kCacheLine) std::atomic<std::size_t> head_{0};  // next slot to pop (consumer)
  std::size_t tail_cache_ = 0;                            // consumer's last view of tail_
  alignas(kCacheLine) std::atomic<std::size_t> tail_{0};  // next slot to push (producer)
  std::size_t head_cache_ = 0;                            // producer's last view of head_
  alignas(kCacheLine) std::array<T, Capacity> slots_{};
};

}  // namespace enact::rt
