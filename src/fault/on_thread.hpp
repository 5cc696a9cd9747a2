// Running a piece of fault handling on a component's own thread, and bounded waits: the two
// ways the fault manager's parts reach a component without racing its callbacks (decision
// 0002: one thread owns a component).
// Thread-safety: any thread.
#pragma once

#include <chrono>
#include <functional>
#include <thread>

#include "keel/component.hpp"

namespace keel::fault {

/// How long a fault stop waits for a hung callback to come back after it was interrupted.
inline constexpr std::chrono::milliseconds kInterruptBound{200};

/// Polls `done` every 50 µs until it is true (true) or `bound` has passed (false).
template <class Pred>
bool waitFor(std::chrono::nanoseconds bound, Pred done) {
  const auto until = std::chrono::steady_clock::now() + bound;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= until) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
  return true;
}

/// Runs `job` on `c`'s own thread (posted to its executor, here when this is that thread, or
/// under a passive component's lock), waiting at most `bound`; false if it did not run in
/// time (it may still run later).
bool onItsThread(Component& c, std::chrono::nanoseconds bound, const std::function<void()>& job);

}  // namespace keel::fault
