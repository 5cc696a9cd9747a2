// keel::components::MovingAverage: the mean of the last `window` samples (the paper's sliding
// window filter, §5.1.3), O(1) per sample over a ring buffer allocated once by reset(); push()
// never allocates. The running sum is recomputed from the buffer each time the ring wraps
// (amortised O(1)), so rounding error cannot build up over a long run.
// Used by SlidingWindowMonitor. Thread-safety: none; owned by one component.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <numeric>
#include <vector>

namespace keel::components {

class MovingAverage {
 public:
  /// Sizes the window (>= 1) and forgets every sample. Allocates; call at initialization.
  void reset(std::size_t window) {
    assert(window >= 1);
    ring_.assign(window, 0.0);
    clear();
  }

  /// Forgets every sample, keeping the window size. Does not allocate.
  void clear() {
    std::fill(ring_.begin(), ring_.end(), 0.0);
    next_ = 0;
    count_ = 0;
    sum_ = 0.0;
  }

  /// Adds a sample (dropping the oldest once full) and returns the new mean.
  double push(double x) {
    assert(!ring_.empty());
    sum_ += x - ring_[next_];  // the slot holds 0 until the window is full
    ring_[next_] = x;
    if (count_ < ring_.size()) ++count_;
    if (++next_ == ring_.size()) {
      next_ = 0;
      sum_ = std::accumulate(ring_.begin(), ring_.end(), 0.0);
    }
    return mean();
  }

  /// Mean of the samples in the window (of those seen so far until it is full; 0 if none).
  double mean() const { return count_ == 0 ? 0.0 : sum_ / static_cast<double>(count_); }
  bool full() const { return !ring_.empty() && count_ == ring_.size(); }
  std::size_t count() const { return count_; }
  std::size_t window() const { return ring_.size(); }

 private:
  std::vector<double> ring_;
  std::size_t next_ = 0;   // slot the next sample goes into
  std::size_t count_ = 0;  // samples held, up to the window
  double sum_ = 0.0;
};

}  // namespace keel::components
