// The runtime side shared by the typed data and event ports, so that keel/data_port.hpp and
// keel/event_port.hpp show only what an author calls: QueuedInput<T> is an input port with its
// queue (the runtime configures it, counts it, clears it and connects outputs to it); Fanout<T>
// is an output port with its list of connections. The runtime's functions are private here and
// reached through the port base classes of keel/detail/port_base.hpp, which authors never name.
// Thread-safety: as PortQueue and Connection; connections are attached before the run starts.
#pragma once

#include <cstddef>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <typeindex>
#include <typeinfo>
#include <utility>
#include <vector>

#include "keel/detail/connection.hpp"
#include "keel/detail/json_form.hpp"
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
        queue_(capacity, QueuePolicy::Fifo) {
    if constexpr (std::is_trivially_copyable_v<T>) this->byte_size_ = sizeof(T);
  }

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
  std::unique_ptr<ByteInlet> makeByteInlet() override {
    if constexpr (std::is_trivially_copyable_v<T>) {
      // The bytes were copied into storage aligned for T: for a trivially copyable type that
      // makes a T there (an implicit-lifetime type), read in place.
      struct Inlet final : ByteInlet {
        explicit Inlet(Sink<T>* sink) : to(sink) {}
        void deliverBytes(const void* value) override { to.send(*std::launder(static_cast<const T*>(value))); }
        ConnectionBase& connection() override { return to; }
        Connection<T> to;
      };
      return std::make_unique<Inlet>(static_cast<Sink<T>*>(this));
    } else {
      return nullptr;
    }
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
      : OutputPortBase(owner, std::move(name), kind, PortDirection::Output, typeid(T), ::keel::typeName<T>()) {
    if constexpr (std::is_trivially_copyable_v<T>) this->byte_size_ = sizeof(T);
  }

  void sendAll(const T& value) const {
    for (const Connection<T>* c : connections_) c->send(value);
  }

 private:
  bool attach(ConnectionBase& connection) override {
    if (connection.type() != std::type_index(typeid(T))) return false;
    connections_.push_back(static_cast<Connection<T>*>(&connection));
    return true;
  }
  std::unique_ptr<ByteEnd> attachBytes(ByteSink& sink) override {
    if constexpr (std::is_trivially_copyable_v<T>) {
      struct Outlet final : ByteEnd, Sink<T> {
        explicit Outlet(ByteSink& s) : bytes(s), from(this) {}
        void deliver(const T& value) override { bytes.deliverBytes(&value); }
        ConnectionBase& connection() override { return from; }
        ByteSink& bytes;
        Connection<T> from;
      };
      auto outlet = std::make_unique<Outlet>(sink);
      connections_.push_back(&outlet->from);
      return outlet;
    } else {
      (void)sink;
      return nullptr;
    }
  }

  static constexpr bool kJson = std::is_trivially_copyable_v<T> && JsonForm<T>::kHas;
  static std::string jsonOf(const void* value) {
    if constexpr (kJson) {
      T v;
      std::memcpy(&v, value, sizeof v);
      std::string out;
      JsonForm<T>::append(out, v);
      return out;
    } else {
      (void)value;
      return {};
    }
  }
  ToJson toJson() const override { return kJson ? &jsonOf : nullptr; }
  const char* jsonType() const override {
    if constexpr (kJson) return JsonForm<T>::schemaType();
    else return nullptr;
  }

  std::vector<const Connection<T>*> connections_;
};

}  // namespace keel::detail
