// keel's side of its OPRoS headers: what an OPRoS port or method hands to keel and back. OPRoS
// component sources never name this header; the port headers include it.
//  - A service call crosses keel's service machinery as one keel port type for every OPRoS
//    service port, `Reply(Call)`: the method's name and its arguments (a std::tuple of the
//    decayed parameter types, type-erased), and the result (empty for void). Which methods a
//    port has is checked against the service type profiles when the run loads.
//  - Adapter (src/opros/adapter.cpp) is the keel component that owns one OPRoS component object.
// Thread-safety: plain values.
#pragma once

#include <any>
#include <string>

namespace keel {
class Component;
}

namespace keel::opros {

class Adapter;

/// One OPRoS method call as keel's service ports carry it.
struct Call {
  std::string method;
  std::any args;  // std::tuple<std::decay_t<P>...> of the call site's arguments
};

/// What the method returned: a value of its return type, or empty for void.
using Reply = std::any;

}  // namespace keel::opros
