// How a message type crosses DDS: keel's C++ port type (keel::msg::<pkg>::<Name>), the C
// sample type CycloneDDS's idlc generates for it, and the conversions between the two. Each
// message's generated code (keel's shipped messages, a user's keel_add_messages) registers one
// DdsType with KEEL_DDS_TYPE; keel's DDS layer (src/dds) finds it by the ROS 2 type name a
// profile's <publish>/<subscribe> gives, and the engine the table of its fields a <validity
// field=".."> names. Authors never name this header; it does not include
// CycloneDDS (the generated code does).
// Thread-safety: registration runs in static initialisers; the rest is reentrant.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <span>
#include <string>
#include <typeindex>
#include <vector>

#include "keel/data_port.hpp"
#include "keel/detail/connection.hpp"
#include "keel/detail/message_fields.hpp"
#include "keel/detail/port_base.hpp"

namespace keel::detail {

/// Memory a conversion to the C sample needs beyond what it can borrow from the C++ value (a
/// sequence of nested messages, a std::vector<bool>): freed after the sample is written.
class DdsScratch {
 public:
  /// Zeroed storage for `n` objects of the C type U (trivial: idlc's types are C structs).
  template <class U>
  U* make(std::size_t n) {
    if (n == 0) return nullptr;
    blocks_.emplace_back(new (std::align_val_t(alignof(std::max_align_t))) std::byte[n * sizeof(U)]());
    return reinterpret_cast<U*>(blocks_.back().get());
  }

 private:
  struct Free {
    void operator()(std::byte* p) const { ::operator delete[](p, std::align_val_t(alignof(std::max_align_t))); }
  };
  std::vector<std::unique_ptr<std::byte[], Free>> blocks_;
};

/// Writes one sample (the C struct at `sample`) with the DDS writer `writer`. False if DDS
/// refused it. Defined in libkeel (src/dds).
bool ddsWrite(std::int32_t writer, const void* sample);

/// One message type, as the DDS layer sees it.
struct DdsType {
  const char* ros_name;    ///< ROS 2's name: "std_msgs/msg/Float64"
  std::type_index type;    ///< the C++ port type
  const void* descriptor;  ///< idlc's dds_topic_descriptor_t for the C sample type
  /// A connection an output port can attach to: each value sent on it is converted and
  /// written by `writer`. It must outlive the port's sends.
  std::unique_ptr<ByteEnd> (*make_outlet)(std::int32_t writer);
  /// Converts one sample (the C struct at `sample`) and sends it on `connection`, a
  /// Connection<T> of this type made by an input port.
  void (*deliver)(const void* sample, ConnectionBase& connection);
  /// An OutputDataPort<T> `name` of `owner`: a port whose values come from DDS (the output of a
  /// ROS 2 node keel watches, on its stand-in).
  std::unique_ptr<PortBase> (*make_output)(Component* owner, std::string name);
  /// Converts one sample and pushes it on `port`, made by make_output: validity checked, sent
  /// to every connected input, as a component's push.
  void (*push)(const void* sample, PortBase& port);
  /// The type's fields by name (message_fields.hpp): what a <validity field=".."> may name.
  std::span<const MessageField> fields;
};

/// Adds `type` to the registry (defined in libkeel). A second registration of a name keeps
/// the first.
void registerDdsType(const DdsType& type);

/// The outlet of a type T whose C sample is C: a connection whose sink converts and writes.
template <class T, class C, void (*ToDds)(const T&, C&, DdsScratch&)>
class DdsOutlet final : public Sink<T>, public ByteEnd {
 public:
  explicit DdsOutlet(std::int32_t writer) : writer_(writer), connection_(this) {}
  ConnectionBase& connection() override { return connection_; }
  void deliver(const T& value) override {
    C sample{};
    DdsScratch scratch;
    ToDds(value, sample, scratch);
    ddsWrite(writer_, &sample);
  }

 private:
  std::int32_t writer_;
  Connection<T> connection_;
};

template <class T, class C, void (*ToDds)(const T&, C&, DdsScratch&), void (*FromDds)(const C&, T&)>
struct DdsTypeOf {
  static std::unique_ptr<ByteEnd> makeOutlet(std::int32_t writer) {
    return std::make_unique<DdsOutlet<T, C, ToDds>>(writer);
  }
  static void deliver(const void* sample, ConnectionBase& connection) {
    T value{};
    FromDds(*static_cast<const C*>(sample), value);
    static_cast<Connection<T>&>(connection).send(value);
  }
  static std::unique_ptr<PortBase> makeOutput(Component* owner, std::string name) {
    return std::make_unique<OutputDataPort<T>>(owner, std::move(name));
  }
  static void push(const void* sample, PortBase& port) {
    T value{};
    FromDds(*static_cast<const C*>(sample), value);
    static_cast<OutputDataPort<T>&>(port).push(value);
  }
};

}  // namespace keel::detail

/// In one .cpp per message (generated): registers the C++ type T, whose C sample type is C
/// with idlc descriptor DESC, converted by TO_DDS(const T&, C&, DdsScratch&) and
/// FROM_DDS(const C&, T&), under the ROS 2 name ROS_NAME, with its fields' table (T's
/// MessageFieldsOf, from the message's __fields.hpp, which the .cpp includes).
#define KEEL_DDS_TYPE(T, C, DESC, TO_DDS, FROM_DDS, ROS_NAME)                                                      \
  namespace {                                                                                                      \
  const bool keel_dds_type_registered_ = [] {                                                                      \
    using Of = ::keel::detail::DdsTypeOf<T, C, TO_DDS, FROM_DDS>;                                                  \
    ::keel::detail::registerDdsType({ROS_NAME, typeid(T), &(DESC), &Of::makeOutlet, &Of::deliver, &Of::makeOutput, \
                                     &Of::push, ::keel::detail::MessageFieldsOf<T>::fields()});                    \
    return true;                                                                                                   \
  }();                                                                                                             \
  }
