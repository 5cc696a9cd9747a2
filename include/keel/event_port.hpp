// Event ports (OPRoS event ports): an OutputEventPort<T> sends events; each connected
// InputEventPort<T> queues them and the runtime delivers them one by one to the receiving
// component's onEvent(port), on that component's own executor. Inside onEvent, `current()`
// is the event being delivered. Thread-safety: send from the owner's callbacks.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "keel/detail/connection.hpp"
#include "keel/detail/port_base.hpp"
#include "keel/detail/port_queue.hpp"
#include "keel/event.hpp"
#include "keel/type_name.hpp"

namespace keel {

/// What onEvent receives: the port an event arrived on.
class InputEventPortBase : public detail::InputPortBase {
 public:
  using InputPortBase::InputPortBase;
  /// Runtime: moves the next queued event into current(); false when none is queued.
  virtual bool takeNext() = 0;
};

template <class T = Event>
class InputEventPort final : public InputEventPortBase, private detail::Sink<T> {
 public:
  InputEventPort(Component* owner, std::string name)
      : InputEventPortBase(owner, std::move(name), detail::PortKind::Event, detail::PortDirection::Input, typeid(T),
                           ::keel::typeName<T>()),
        queue_(64, detail::QueuePolicy::Fifo) {}

  /// The event being delivered (valid inside onEvent for this port).
  const T& current() const { return current_; }

  // ---- runtime side ----
  bool takeNext() override {
    std::optional<T> next = queue_.pop();
    if (!next) return false;
    current_ = std::move(*next);
    return true;
  }
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
    queue_.push(value);
    detail::notifyInput(owner(), true);
  }
  detail::PortQueue<T> queue_;
  T current_{};
};

template <class T = Event>
class OutputEventPort final : public detail::OutputPortBase {
 public:
  OutputEventPort(Component* owner, std::string name)
      : OutputPortBase(owner, std::move(name), detail::PortKind::Event, detail::PortDirection::Output, typeid(T),
                       ::keel::typeName<T>()) {}

  /// Sends `event` to every connected input event port.
  void send(const T& event) {
    for (const detail::Connection<T>* c : connections_) c->send(event);
  }
  /// Alias of send, for symmetry with data ports.
  void push(const T& event) { send(event); }

  bool attach(detail::ConnectionBase& connection) override {
    if (connection.type() != std::type_index(typeid(T))) return false;
    connections_.push_back(static_cast<detail::Connection<T>*>(&connection));
    return true;
  }

 private:
  std::vector<const detail::Connection<T>*> connections_;
};

}  // namespace keel
