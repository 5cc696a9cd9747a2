#include "monitor/port_tap.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "runtime/clock.hpp"
#include "runtime/port_access.hpp"

namespace keel::monitor {

PortTap::PortTap(detail::OutputPortBase& port, std::size_t capacity)
    : port_(port), to_json_(detail::PortAccess::toJson(port)), value_size_(port.byteSize()),
      slot_size_(1 + (value_size_ + 7) / 8),
      mask_(std::min(std::bit_ceil(std::max(capacity, std::size_t{2})),
                     std::bit_floor(std::max(kMaxRingBytes / (8 * slot_size_), std::size_t{2}))) -
            1),
      slots_((mask_ + 1) * slot_size_), newest_(std::make_unique<std::atomic<std::uint64_t>[]>(slot_size_)) {}

PortTap::~PortTap() = default;

bool PortTap::attach() {
  if (value_size_ == 0 || to_json_ == nullptr || slot_size_ > kMaxWords) return false;
  end_ = port_.attachBytes(*this);
  return end_ != nullptr;
}

void PortTap::deliverBytes(const void* value) {
  if (!active_.load(std::memory_order_acquire)) {
    std::uint64_t words[kMaxWords];
    words[0] = static_cast<std::uint64_t>(runtime::steadyNs());
    std::memcpy(words + 1, value, value_size_);
    // Odd while being written; the acquire half keeps the words' stores after it (no fences:
    // ThreadSanitizer does not model them).
    const std::uint64_t seq = newest_seq_.fetch_add(1, std::memory_order_acq_rel);
    for (std::size_t i = 0; i < slot_size_; ++i) newest_[i].store(words[i], std::memory_order_relaxed);
    newest_seq_.store(seq + 2, std::memory_order_release);
    return;
  }
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  if (head - tail_.load(std::memory_order_acquire) > mask_) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  std::uint64_t* slot = &slots_[(head & mask_) * slot_size_];
  slot[0] = static_cast<std::uint64_t>(runtime::steadyNs());
  std::memcpy(slot + 1, value, value_size_);
  head_.store(head + 1, std::memory_order_release);
  taken_.fetch_add(1, std::memory_order_relaxed);
}

bool PortTap::newest(const std::function<void(std::int64_t, const std::string&)>& each) {
  std::uint64_t words[kMaxWords] = {};
  for (;;) {
    const std::uint64_t before = newest_seq_.load(std::memory_order_acquire);
    if (before == 0) return false;  // nothing sent yet
    if (before % 2 == 1) continue;  // being written
    // Acquire loads: the check of the sequence below cannot move before them.
    for (std::size_t i = 0; i < slot_size_; ++i) words[i] = newest_[i].load(std::memory_order_acquire);
    if (newest_seq_.load(std::memory_order_relaxed) == before) break;
  }
  each(static_cast<std::int64_t>(words[0]), to_json_(words + 1));
  return true;
}

void PortTap::drain(const std::function<void(std::int64_t, const std::string&)>& each) {
  std::uint64_t tail = tail_.load(std::memory_order_relaxed);
  const std::uint64_t head = head_.load(std::memory_order_acquire);
  for (; tail != head; ++tail) {
    const std::uint64_t* slot = &slots_[(tail & mask_) * slot_size_];
    each(static_cast<std::int64_t>(slot[0]), to_json_(slot + 1));
    tail_.store(tail + 1, std::memory_order_release);  // the slot is free once read
  }
}

}  // namespace keel::monitor
