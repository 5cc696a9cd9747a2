// Data ports (OPRoS data ports): an OutputDataPort<T> pushes values to every connected
// InputDataPort<T>, which queues them by the policy its profile names (FIFO, UFIFO, LIFO,
// LAST; see detail/port_queue.hpp). Types are checked when the runtime connects ports.
// In-process delivery copies the value into the receiver's preallocated queue: no allocation
// for fixed-size T. Thread-safety: push from the owner's callbacks; pop/peek likewise.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "keel/detail/connection.hpp"
#include "keel/detail/port_base.hpp"
#include "keel/detail/port_queue.hpp"
#include "keel/type_name.hpp"

namespace keel {

template <class T>
class InputDataPort final : public detail::InputPortBase, private detail::Sink<T> {
 public:
  InputDataPort(Component* owner, std::string name)
      : InputPortBase(owner, std::move(name), detail::PortKind::Data, detail::PortDirection::Input, typeid(T),
                      ::keel::typeName<T>()) {}

  /// The next value by the queue policy, or nothing if the queue is empty.
  std::optional<T> pop() { return queue_.pop(); }
  /// The value pop() would return, left in the queue.
  std::optional<T> peek() const { return queue_.peek(); }
  bool empty() const { return queue_.size() == 0; }
  bool numeric() const override { return detail::NumericTraits<T>::numeric; }

  // ---- runtime side ----
  void configureQueue(detail::QueuePolicy policy, std::size_t size) override { queue_.configure(policy, size); }
  std::size_t capacity() const override { return queue_.capacity(); }
  std::size_t queued() const override { return queue_.size(); }
  std::size_t dropped() const override { return queue_.dropped(); }
  void clear() override { queue_.clear(); }
  std::unique_ptr<detail::ConnectionBase> makeConnection() override {
    return std::make_unique<detail::Connection<T>>(static_cast<detail::Sink<T>*>(this));
  }
  bool retarget(detail::ConnectionBase& c) override {
    if (c.type() != std::type_index(typeid(T))) return false;
    static_cast<detail::Connection<T>&>(c).retarget(this);
    return true;
  }

 private:
  void deliver(const T& value) override {
    if constexpr (detail::NumericTraits<T>::numeric) {
      detail::Violation v;
      if (validity_ && !validity_->check(value, v)) [[unlikely]] {
        detail::reportRange(owner(), name(), v, true);
        return;  // an invalid value is not queued
      }
    }
    queue_.push(value);
    detail::notifyInput(owner(), false);
  }
  detail::PortQueue<T> queue_;
};

template <class T>
class OutputDataPort final : public detail::OutputPortBase {
 public:
  OutputDataPort(Component* owner, std::string name)
      : OutputPortBase(owner, std::move(name), detail::PortKind::Data, detail::PortDirection::Output, typeid(T),
                       ::keel::typeName<T>()) {}

  /// Sends `value` to every connected input. A value that violates the port's validity rule
  /// is a `range` fault of this component and is not sent.
  void push(const T& value) {
    if constexpr (detail::NumericTraits<T>::numeric) {
      if (corrupt_next_.load(std::memory_order_relaxed)) [[unlikely]] {
        pushCorrupted(value);
        return;
      }
      detail::Violation v;
      if (validity_ && !validity_->check(value, v)) [[unlikely]] {
        detail::reportRange(owner(), name(), v, false);
        return;
      }
    }
    for (const detail::Connection<T>* c : connections_) c->send(value);
  }
  bool numeric() const override { return detail::NumericTraits<T>::numeric; }
  std::size_t connections() const { return connections_.size(); }

  // ---- runtime side ----
  bool attach(detail::ConnectionBase& connection) override {
    if (connection.type() != std::type_index(typeid(T))) return false;
    connections_.push_back(static_cast<detail::Connection<T>*>(&connection));
    return true;
  }

 private:
  void pushCorrupted(T value) {
    // acquire: pairs with corruptNext()'s release, so corrupt_value_ is the injector's.
    if (!corrupt_next_.exchange(false, std::memory_order_acquire)) return push(value);
    detail::NumericTraits<T>::fill(value, corrupt_value_);
    detail::noteInjectedCorruption(owner());
    push(value);
    detail::endInjectedCorruption();
  }

  std::vector<const detail::Connection<T>*> connections_;
};

}  // namespace keel
