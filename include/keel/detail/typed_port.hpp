// The runtime side shared by the typed data and event ports, so that keel/data_port.hpp and
// keel/event_port.hpp show only what an author calls: QueuedInput<T> is an input port with its
// queue (the runtime configures it, counts it, clears it and connects outputs to it); Fanout<T>
// is an output port with its list of connections. The runtime's functions are private here and
// reached through the port base classes of keel/detail/port_base.hpp, which authors never name.
// Thread-safety: as PortQueue and Connection; connections are attached before the run starts.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <typeindex>
#include <typeinfo>
#include <utility>
#include <vector>

#include "keel/detail/connection.hpp"
#include "keel/detail/port_base.hpp"
#include "keel/detail/port_queue.hpp"
#include "keel/type_name.hpp"

namespace keel::detail {

/// An input port of values of type T queued for its owner. `Base` is InputPortBase or
/// InputEventPortBase. The derived port implements `deliver` (what arriving values do).
template <class T, class Base>
class QueuedInput : public Base, private Sink<T> {
 protected:
  QueuedInput(Component* owner, std::string name, PortKind kind, std::size_t capacity)
      : Base(owner, std::move(name), kind, PortDirection::Input, typeid(T), ::keel::typeName<T>()),
        queue_(capacity, QueuePolicy::Fifo) {}

  PortQueue<T> queue_;

 private:
  void configureQueue(QueuePolicy policy, std::size_t size) override { queue_.configure(policy, size); }
  std::size_t capacity() const override { return queue_.capacity(); }
  std::size_t queued() const override { return queue_.size(); }
  std::size_t dropped() const override { return queue_.dropped(); }
  void clear() override { queue_.clear(); }
  std::unique_ptr<ConnectionBase> makeConnection() override {
    return std::make_unique<Connection<T>>(static_cast<Sink<T>*>(this));
  }
  bool retarget(ConnectionBase& c) override {
    if (c.type() != std::type_index(typeid(T))) return false;
    static_cast<Connection<T>&>(c).retarget(this);
    return true;
  }
};

/// An output port that sends values of type T to every connected input.
template <class T>
class Fanout : public OutputPortBase {
 public:
  /// How many inputs this port is connected to.
  std::size_t connections() const { return connections_.size(); }

 protected:
  Fanout(Component* owner, std::string name, PortKind kind)
      : OutputPortBase(owner, std::move(name), kind, PortDirection::Output, typeid(T), ::keel::typeName<T>()) {}

  void sendAll(const T& value) const {
    for (const Connection<T>* c : connections_) c->send(value);
  }

 private:
  bool attach(ConnectionBase& connection) override {
    if (connection.type() != std::type_index(typeid(T))) return false;
    connections_.push_back(static_cast<Connection<T>*>(&connection));
    return true;
  }

  std::vector<const Connection<T>*> connections_;
};

}  // namespace keel::detail
