// Event ports (OPRoS event ports): an OutputEventPort<T> sends events; each connected
// InputEventPort<T> queues them and the runtime delivers them one by one to the receiving
// component's onEvent(port), on that component's own executor. Inside onEvent, `current()`
// is the event being delivered. Thread-safety: send from the owner's callbacks.
#pragma once

#include <optional>
#include <string>

#include "keel/detail/typed_port.hpp"
#include "keel/event.hpp"

namespace keel {

/// What onEvent receives: the port an event arrived on.
class InputEventPortBase : public detail::InputPortBase {
 public:
  using InputPortBase::InputPortBase;

 private:
  friend struct detail::PortAccess;
  /// Moves the next queued event into current(); false when none is queued (the runtime).
  virtual bool takeNext() = 0;
};

template <class T = Event>
class InputEventPort final : public detail::QueuedInput<T, InputEventPortBase> {
 public:
  InputEventPort(Component* owner, std::string name)
      : detail::QueuedInput<T, InputEventPortBase>(owner, std::move(name), PortKind::Event, 64) {}

  /// The event being delivered (valid inside onEvent for this port).
  const T& current() const { return current_; }

 private:
  bool takeNext() override {
    std::optional<T> next = this->queue_.pop();
    if (!next) return false;
    current_ = std::move(*next);
    return true;
  }
  void deliver(const T& value) override {
    this->queue_.push(value);
    detail::notifyInput(this->owner(), true);
  }
  T current_{};
};

template <class T = Event>
class OutputEventPort final : public detail::Fanout<T> {
 public:
  OutputEventPort(Component* owner, std::string name) : detail::Fanout<T>(owner, std::move(name), PortKind::Event) {}

  /// Sends `event` to every connected input event port.
  void send(const T& event) { this->sendAll(event); }
  /// Alias of send, for symmetry with data ports.
  void push(const T& event) { send(event); }
};

}  // namespace keel
