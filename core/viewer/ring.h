#pragma once
// A fixed-capacity ring of the latest values (scrolling plots, trails): push overwrites the
// oldest once full; index 0 is the oldest kept. Never allocates after construction.
#include <array>
#include <cstddef>

namespace enact::viewer {

template <class T, std::size_t Capacity>
class Ring {
 public:
  // append, dropping the oldest when full
  void push(const T& v) {
    data_[(start_ + size_) % Capacity] = v;
    if (size_ < Capacity) ++size_;
    else start_ = (start_ + 1) % Capacity;
  }
  void clear() { start_ = size_ = 0; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  static constexpr std::size_t capacity() { return Capacity; }
  // i-th oldest, 0 <= i < size()
  const T& operator[](std::size_t i) const { return data_[(start_ + i) % Capacity]; }
  const T& back() const { return (*this)[size_ - 1]; }
  // raw storage and the index of the oldest value, for ImGui::PlotLines(values, count, offset)
  const T* data() const { return data_.data(); }
  std::size_t offset() const { return size_ < Capacity ? 0 : start_; }

 private:
  std::array<T, Capacity> data_{};
  std::size_t start_ = 0;
  std::size_t size_ = 0;
};

}  // namespace enact::viewer
