// Alarm: a one-shot timer one thread sleeps on and another sets (a timerfd). Setting it is one
// system call that wakes nobody until the time comes: a thread on a latency-critical path can
// hand a sleeper a wake-up for later (after its own work, or at a deadline) without paying for
// the sleeper's wake-up now. Not armed, it never fires.
// Thread-safety: wait() on one thread; setIn() from any thread. Const: the timer's state is the
// kernel's.
#pragma once

#include <chrono>

#include "keel/result.hpp"

namespace keel::runtime {

class Alarm {
 public:
  static Result<Alarm> create();
  Alarm() = default;  // not usable: create()
  ~Alarm();
  Alarm(Alarm&& other) noexcept;
  Alarm& operator=(Alarm&& other) noexcept;
  Alarm(const Alarm&) = delete;
  Alarm& operator=(const Alarm&) = delete;

  /// Fires `after` from now (at once for 0 or less), replacing any earlier setting.
  void setIn(std::chrono::nanoseconds after) const;
  /// Sleeps until it fires (for ever if it is never set).
  void wait() const;

 private:
  explicit Alarm(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace keel::runtime
