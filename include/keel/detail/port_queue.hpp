// The queue behind an input port, with OPRoS's policies:
//   FIFO  bounded; when full the oldest value is dropped
//   UFIFO unbounded FIFO (grows; allocates only when it outgrows its capacity)
//   LIFO  bounded; pop returns the newest; when full the oldest is dropped
//   LAST  holds only the latest value
// Storage is allocated when configured, so push/pop of a fixed-size T never allocate.
// Thread-safety: any number of producers and consumers (one short critical section each).
#pragma once

#include <cstddef>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "keel/detail/port_base.hpp"

namespace keel::detail {

template <class T>
class PortQueue {
 public:
  explicit PortQueue(std::size_t capacity = 16, QueuePolicy policy = QueuePolicy::Fifo) { configure(policy, capacity); }

  void configure(QueuePolicy policy, std::size_t capacity) {
    std::lock_guard lock(mutex_);
    policy_ = policy;
    if (policy == QueuePolicy::Last) capacity = 1;
    if (capacity == 0) capacity = 1;
    ring_.clear();
    ring_.resize(capacity);
    head_ = size_ = 0;
  }

  /// Returns true when a value had to be dropped to make room.
  bool push(const T& value) {
    std::lock_guard lock(mutex_);
    bool dropped_one = false;
    if (size_ == ring_.size()) {
      if (policy_ == QueuePolicy::UFifo) {
        grow();
      } else {  // drop the oldest
        ring_[head_].reset();
        head_ = (head_ + 1) % ring_.size();
        --size_;
        ++dropped_;
        dropped_one = true;
      }
    }
    ring_[(head_ + size_) % ring_.size()].emplace(value);
    ++size_;
    return dropped_one;
  }

  std::optional<T> pop() {
    std::lock_guard lock(mutex_);
    if (size_ == 0) return std::nullopt;
    std::optional<T> out;
    if (policy_ == QueuePolicy::Lifo) {
      out = std::exchange(ring_[(head_ + size_ - 1) % ring_.size()], std::nullopt);
    } else {
      out = std::exchange(ring_[head_], std::nullopt);
      head_ = (head_ + 1) % ring_.size();
    }
    --size_;
    return out;
  }

  std::optional<T> peek() const {
    std::lock_guard lock(mutex_);
    if (size_ == 0) return std::nullopt;
    if (policy_ == QueuePolicy::Lifo) return ring_[(head_ + size_ - 1) % ring_.size()];
    return ring_[head_];
  }

  std::size_t size() const {
    std::lock_guard lock(mutex_);
    return size_;
  }
  std::size_t capacity() const {
    std::lock_guard lock(mutex_);
    return ring_.size();
  }
  std::size_t dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
  }
  void clear() {
    std::lock_guard lock(mutex_);
    for (auto& slot : ring_) slot.reset();
    head_ = size_ = 0;
  }

 private:
  void grow() {  // UFIFO only; called with the lock held
    std::vector<std::optional<T>> bigger(ring_.size() * 2);
    for (std::size_t i = 0; i < size_; ++i) bigger[i] = std::move(ring_[(head_ + i) % ring_.size()]);
    ring_ = std::move(bigger);
    head_ = 0;
  }

  mutable std::mutex mutex_;
  std::vector<std::optional<T>> ring_;
  std::size_t head_ = 0;
  std::size_t size_ = 0;
  std::size_t dropped_ = 0;
  QueuePolicy policy_ = QueuePolicy::Fifo;
};

}  // namespace keel::detail
