// OPRoS's execution order, `<coordination><depends source="a" target="b"/>` (docs/opros.md):
// a's onExecute runs only when every one of its targets has executed since a last ran, at most
// once however many times they did. Each component in such an order has a gate: counters, one
// per target, that the targets' executors raise after each onExecute, and the gates of its
// followers to raise in turn. A primary and its replacement share their instance's gate.
// Thread-safety: open() and ran() on the executor thread of the gate's component; raise() from
// any (the targets' executors).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

namespace keel::runtime {

class ExecutionGate {
 public:
  /// A counter for one more target; its index, for a follower entry of that target's gate.
  std::size_t addTarget() { return targets_++; }
  /// After each onExecute of this gate's component, raise counter `index` of `follower`.
  void addFollower(ExecutionGate& follower, std::size_t index) { followers_.emplace_back(&follower, index); }
  /// Allocates the counters; call once, after every addTarget, before the run starts.
  void freeze() { counts_ = std::make_unique<std::atomic<std::uint32_t>[]>(targets_); }

  /// Whether the component may execute now: every target ran since it last did. If so, the
  /// counters are consumed (a target that runs during this execution counts for the next).
  bool open() {
    for (std::size_t i = 0; i < targets_; ++i)
      if (counts_[i].load(std::memory_order_acquire) == 0) return false;
    for (std::size_t i = 0; i < targets_; ++i) counts_[i].store(0, std::memory_order_relaxed);
    return true;
  }
  /// The component executed: its followers may run once more.
  void ran() {
    for (auto& [gate, index] : followers_) gate->counts_[index].fetch_add(1, std::memory_order_release);
  }

 private:
  std::size_t targets_ = 0;
  std::unique_ptr<std::atomic<std::uint32_t>[]> counts_;
  std::vector<std::pair<ExecutionGate*, std::size_t>> followers_;
};

}  // namespace keel::runtime
