// A connection as made, and the ports on its two sides: between two components of this process,
// or between one of them and a transport that carries it further (a ring to another process, a
// DDS topic), whose side has no port here. The engine keeps one per connection, so that a
// replacement re-points the connections of the component it replaces.
// Thread-safety: a plain value.
#pragma once

#include "keel/detail/port_base.hpp"

namespace keel::runtime {

struct Wire {
  detail::ConnectionBase* connection = nullptr;  // null for a service binding
  detail::PortBase* source = nullptr;            // output port, or required service port; null: a transport's
  detail::PortBase* target = nullptr;            // input port, or provided service port; null: a transport's
};

}  // namespace keel::runtime
