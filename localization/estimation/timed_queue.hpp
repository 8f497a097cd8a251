#pragma once
// TimedQueue: a fixed-capacity FIFO of timestamped items kept in time order (a ring buffer: pushing
// and popping never allocate after construction). The estimator queues navdata and commands in it
// until the filter reaches their time.
#include <cassert>
#include <cstddef>
#include <vector>

#include "core/time.hpp"

namespace labo::estimation {

template <typename T>
class TimedQueue {
 public:
  struct Entry {
    Seconds t = 0;  // the time the item applies at
    T item{};
  };

  explicit TimedQueue(std::size_t capacity) : buffer_(capacity) { assert(capacity > 0); }

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ == buffer_.size(); }
  std::size_t capacity() const { return buffer_.size(); }

  // The caller keeps times non-decreasing (checked by the estimator before pushing).
  void push(Seconds t, const T& item) {
    assert(!full());
    buffer_[(head_ + size_) % buffer_.size()] = Entry{t, item};
    ++size_;
  }
  const Entry& front() const { return at(0); }
  const Entry& back() const { return at(size_ - 1); }
  const Entry& at(std::size_t i) const { return buffer_[(head_ + i) % buffer_.size()]; }
  void pop() {
    assert(size_ > 0);
    head_ = (head_ + 1) % buffer_.size();
    --size_;
  }
  void clear() { head_ = size_ = 0; }

 private:
  std::vector<Entry> buffer_;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace labo::estimation
