// A port's values for the live monitor (`/keel/ports/<component>/<port>`, docs/monitor.md): a
// second connection of an output port, made before the run starts, that copies each value with
// its time into a ring of its own while the monitor wants them — a client subscribes, or the
// run is recorded — and otherwise keeps only the newest (a client that subscribes later sees
// what the port last sent, even from a component that has stopped). The monitor's hub drains
// the ring and makes the JSON, off the component's thread. A full ring drops the value,
// counted: the component never waits.
// Thread-safety: one producer (the port's owner, on whichever thread runs it) and one consumer
// (the hub); setActive from any thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "keel/detail/port_base.hpp"

namespace keel::monitor {

class PortTap final : public detail::ByteSink {
 public:
  /// The largest value a tap takes, in 8-byte words with its time: 504 bytes (a pose, a
  /// sonar ring, a small map; an image is not shown).
  static constexpr std::size_t kMaxWords = 64;
  /// A ring's size at most: large values get fewer slots.
  static constexpr std::size_t kMaxRingBytes = std::size_t{2} << 20;

  /// Holds up to `capacity` (rounded up to a power of two) values between two drains, fewer
  /// (a power of two) when that many would take more than kMaxRingBytes.
  PortTap(detail::OutputPortBase& port, std::size_t capacity);
  ~PortTap() override;
  PortTap(const PortTap&) = delete;
  PortTap& operator=(const PortTap&) = delete;

  /// Connects the tap to its port; false when its values cannot be copied (not trivially
  /// copyable) or have no JSON form. Before the run starts: a port's connections are fixed
  /// from then on.
  bool attach();
  void setActive(bool active) { active_.store(active, std::memory_order_release); }
  bool active() const { return active_.load(std::memory_order_acquire); }

  /// The port's owner sends a value (byteSize() bytes at `value`).
  void deliverBytes(const void* value) override;

  /// Hands every value taken since the last drain to `each(steady_ns, json)`, oldest first.
  void drain(const std::function<void(std::int64_t, const std::string&)>& each);
  /// The newest value sent while the tap was not active, as in drain(); false when none was.
  bool newest(const std::function<void(std::int64_t, const std::string&)>& each);
  /// Values lost: the ring was full (the hub was behind).
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t taken() const { return taken_.load(std::memory_order_relaxed); }
  /// How many values the ring holds.
  std::size_t capacity() const { return mask_ + 1; }

 private:
  detail::OutputPortBase& port_;  // until attach(): the port may be gone before the last drain
  detail::ToJson to_json_;
  std::size_t value_size_;
  std::size_t slot_size_;  // the time, then the value, padded to 8 bytes
  std::size_t mask_;
  std::vector<std::uint64_t> slots_;  // 8-byte words: every slot aligned for any value
  std::unique_ptr<detail::ByteEnd> end_;
  std::atomic<bool> active_{false};
  alignas(64) std::atomic<std::uint64_t> head_{0};  // next slot the producer writes
  alignas(64) std::atomic<std::uint64_t> tail_{0};  // next slot the consumer reads
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> taken_{0};
  // The newest value while inactive, under a sequence lock (odd: being written); its words are
  // atomics so that a read racing a write is a retry, not a data race.
  std::atomic<std::uint64_t> newest_seq_{0};
  std::unique_ptr<std::atomic<std::uint64_t>[]> newest_;
};

}  // namespace keel::monitor
