// Data ports (OPRoS data ports): an OutputDataPort<T> pushes values to every connected
// InputDataPort<T>, which queues them by the policy its profile names (FIFO, UFIFO, LIFO,
// LAST; see detail/port_queue.hpp). Types are checked when the runtime connects ports.
// In-process delivery copies the value into the receiver's preallocated queue: no allocation
// for fixed-size T. Thread-safety: push from the owner's callbacks; pop/peek likewise.
#pragma once

#include <atomic>
#include <optional>
#include <string>

#include "keel/detail/typed_port.hpp"

namespace keel {

template <class T>
class InputDataPort final : public detail::QueuedInput<T, detail::InputPortBase> {
 public:
  InputDataPort(Component* owner, std::string name)
      : detail::QueuedInput<T, detail::InputPortBase>(owner, std::move(name), PortKind::Data, 16) {}

  /// The next value by the queue policy, or nothing if the queue is empty.
  std::optional<T> pop() { return this->queue_.pop(); }
  /// The value pop() would return, left in the queue.
  std::optional<T> peek() const { return this->queue_.peek(); }
  bool empty() const { return this->queue_.size() == 0; }
  /// How many values wait in the queue.
  std::size_t size() const { return this->queue_.size(); }
  bool numeric() const override { return detail::NumericTraits<T>::numeric; }

 private:
  void deliver(const T& value) override {
    if constexpr (detail::NumericTraits<T>::numeric) {
      detail::Violation v;
      if (this->validity_ && !this->validity_->check(value, v)) [[unlikely]] {
        detail::reportRange(this->owner(), this->name(), v, true);
        return;  // an invalid value is not queued
      }
    } else if (this->field_rules_) [[unlikely]] {
      if (!detail::checkFields(*this->field_rules_, &value, this->owner(), this->name(), true)) return;
    }
    this->queue_.push(value);
    detail::notifyInput(this->owner(), false);
  }
};

template <class T>
class OutputDataPort final : public detail::Fanout<T> {
 public:
  OutputDataPort(Component* owner, std::string name) : detail::Fanout<T>(owner, std::move(name), PortKind::Data) {}

  /// Sends `value` to every connected input. A value that violates the port's validity rule
  /// (or, for a message, a rule of one of its fields) is a `range` fault of this component and
  /// is not sent.
  void push(const T& value) {
    if constexpr (detail::NumericTraits<T>::numeric) {
      if (corrupt_next_.load(std::memory_order_relaxed)) [[unlikely]] {
        pushCorrupted(value);
        return;
      }
      detail::Violation v;
      if (this->validity_ && !this->validity_->check(value, v)) [[unlikely]] {
        detail::reportRange(this->owner(), this->name(), v, false);
        return;
      }
    } else if (this->field_rules_) [[unlikely]] {
      if (!detail::checkFields(*this->field_rules_, &value, this->owner(), this->name(), false)) return;
    }
    this->sendAll(value);
  }
  bool numeric() const override { return detail::NumericTraits<T>::numeric; }

 private:
  bool corruptNext(double value) override {
    if (!detail::NumericTraits<T>::numeric) return false;
    corrupt_value_ = value;
    corrupt_next_.store(true, std::memory_order_release);  // publishes corrupt_value_
    return true;
  }
  void pushCorrupted(T value) {
    // acquire: pairs with corruptNext()'s release, so corrupt_value_ is the injector's.
    if (!corrupt_next_.exchange(false, std::memory_order_acquire)) return push(value);
    detail::NumericTraits<T>::fill(value, corrupt_value_);
    detail::noteInjectedCorruption(this->owner());
    push(value);
    detail::endInjectedCorruption();
  }

  std::atomic<bool> corrupt_next_{false};  // fault injection (`out_of_range`) armed
  double corrupt_value_ = 0;
};

}  // namespace keel
