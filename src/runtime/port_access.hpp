// The runtime's access to the parts of a port its author does not see (keel/detail/port_base.hpp
// and keel/event_port.hpp befriend this): the validity rule, an injected corruption, the next
// event. Included by the runtime and the layers above; never by a component.
// Thread-safety: setValidity and setFieldRules before the run starts; corruptNext from any thread; takeNext on
// the owner's executor.
#pragma once

#include "keel/detail/port_base.hpp"
#include "keel/event_port.hpp"

namespace keel::detail {

struct PortAccess {
  /// Sets `port`'s validity rule; null removes it.
  static void setValidity(PortBase& port, const ValidityRule* rule) { port.validity_ = rule; }
  /// Sets the rules per field of `port`, whose type must be the message the rules were
  /// resolved in; null removes them.
  static void setFieldRules(PortBase& port, const FieldRules* rules) { port.field_rules_ = rules; }
  static const FieldRules* fieldRules(const PortBase& port) { return port.field_rules_; }
  /// Arms `out_of_range` injection on `port`: its next value is replaced by `value`. False if
  /// the port cannot carry it (not a numeric data port).
  static bool corruptNext(OutputPortBase& port, double value) { return port.corruptNext(value); }
  /// The live monitor: how `port`'s values are written as JSON, and their JSON Schema type
  /// (null, null: they have no JSON form).
  static ToJson toJson(const OutputPortBase& port) { return port.toJson(); }
  static const char* jsonType(const OutputPortBase& port) { return port.jsonType(); }
  /// Moves `port`'s next queued event into its current(); false when none is queued.
  static bool takeNext(InputEventPortBase& port) { return port.takeNext(); }
};

}  // namespace keel::detail
