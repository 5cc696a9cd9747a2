// What every port has in common, as seen by the runtime: owner, name, kind, direction and data
// type. Ports register themselves with their owning component on construction, which is how
// the runtime checks code against the profile. Authors never name this header.
// Thread-safety: identity fields are immutable after construction.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <typeindex>

#include "keel/detail/enums.hpp"
#include "keel/detail/validity.hpp"

namespace keel {
class Component;
}

namespace keel::detail {

class PortBase;
class ConnectionBase;

/// Where the bytes of values go when a connection crosses processes: the transport's side of
/// a port whose type is trivially copyable (keel's process isolation; src/runtime/ipc).
class ByteSink {
 public:
  virtual ~ByteSink() = default;
  /// One value: byteSize() bytes at `value`, aligned for the port's type.
  virtual void deliverBytes(const void* value) = 0;
};

/// The in-process connection behind a transport's end (an inlet delivering into an input
/// port, an outlet an output port sends to): what the runtime re-points when a component is
/// replaced.
class ByteEnd {
 public:
  virtual ~ByteEnd() = default;
  virtual ConnectionBase& connection() = 0;
};

/// Values arriving as bytes, delivered into an input port.
class ByteInlet : public ByteSink, public ByteEnd {};
/// The runtime's access to what ports keep from their authors (src/runtime/port_access.hpp).
struct PortAccess;

/// Registers `port` with `owner` (defined in libkeel).
void registerPort(Component* owner, PortBase* port);

class PortBase {
 public:
  PortBase(Component* owner, std::string name, PortKind kind, PortDirection direction, std::type_index type,
           std::string type_name)
      : owner_(owner), name_(std::move(name)), kind_(kind), direction_(direction), type_(type),
        type_name_(std::move(type_name)) {
    registerPort(owner, this);
  }
  virtual ~PortBase() = default;
  PortBase(const PortBase&) = delete;
  PortBase& operator=(const PortBase&) = delete;

  Component& owner() const { return *owner_; }
  const std::string& name() const { return name_; }
  PortKind kind() const { return kind_; }
  PortDirection direction() const { return direction_; }
  std::type_index type() const { return type_; }
  const std::string& typeName() const { return type_name_; }

  /// Whether values can be range-checked (numbers and arrays of numbers).
  virtual bool numeric() const { return false; }
  /// Whether values can cross to another process as bytes (a trivially copyable type), and
  /// how many bytes one is; 0 for a port that cannot (service ports, other types).
  std::size_t byteSize() const { return byte_size_; }

 protected:
  /// Set by the typed ports: sizeof(T) when T is trivially copyable.
  std::size_t byte_size_ = 0;
  /// The port's validity rule (set by the runtime before start); null: none.
  const ValidityRule* validity_ = nullptr;
  /// A message port's rules per field (set by the runtime before start); null: none.
  const FieldRules* field_rules_ = nullptr;

 private:
  friend struct PortAccess;
  Component* owner_;
  std::string name_;
  PortKind kind_;
  PortDirection direction_;
  std::type_index type_;
  std::string type_name_;
};

/// A link from one output port to one input port (data or event). The output holds a list of
/// these; the target can be re-pointed atomically at run time (component replacement). This is
/// the transport seam: an in-process connection delivers into the input port's queue; a
/// remote transport implements the same interface.
class ConnectionBase {
 public:
  virtual ~ConnectionBase() = default;
  virtual std::type_index type() const = 0;
};

/// Input side of a data or event connection: the runtime creates connections from here.
class InputPortBase : public PortBase {
 public:
  using PortBase::PortBase;
  /// Applies the profile's queue policy and size (before the component starts).
  virtual void configureQueue(QueuePolicy policy, std::size_t size) = 0;
  /// Queue capacity (1 for LAST; grows for UFIFO).
  virtual std::size_t capacity() const = 0;
  /// Number of queued values.
  virtual std::size_t queued() const = 0;
  /// Values dropped because the queue was full (FIFO/LIFO) or overwritten (LAST).
  virtual std::size_t dropped() const = 0;
  virtual void clear() = 0;
  /// A new connection whose sink is this port.
  virtual std::unique_ptr<ConnectionBase> makeConnection() = 0;
  /// Points an existing connection at this port (component replacement); false on type mismatch.
  virtual bool retarget(ConnectionBase& connection) = 0;
  /// A way in for values from another process: a sink of bytes that delivers each value as a
  /// connection from an output port of this process would. Null when byteSize() is 0.
  virtual std::unique_ptr<ByteInlet> makeByteInlet() = 0;
};

/// Writes a value (a port type's bytes at `value`) as JSON.
using ToJson = std::string (*)(const void* value);

/// Output side: attaches to connections of the same type.
class OutputPortBase : public PortBase {
 public:
  using PortBase::PortBase;
  /// Adds a connection; false if its type differs from this port's.
  virtual bool attach(ConnectionBase& connection) = 0;
  /// Adds a connection whose values go to `sink` as bytes (to another process); it must live
  /// as long as the port sends. Null when byteSize() is 0.
  virtual std::unique_ptr<ByteEnd> attachBytes(ByteSink& sink) = 0;

 private:
  friend struct PortAccess;
  /// Fault injection (`out_of_range`): the next value pushed is replaced by `value` (every
  /// element of an array). False if this port cannot carry it (only numeric data ports can).
  virtual bool corruptNext(double value) {
    (void)value;
    return false;
  }
  /// The live monitor: how a value of this port's type (byteSize() bytes) is written as JSON,
  /// or null when the type has no JSON form (keel/detail/json_form.hpp). A plain function, so
  /// values taken before the port was destroyed can still be written after.
  virtual ToJson toJson() const { return nullptr; }
  /// The JSON Schema type of those values, or null.
  virtual const char* jsonType() const { return nullptr; }
};

}  // namespace keel::detail
