// Fault injection, the runtime side (SPEC §6): an injection armed on a component fires inside
// its next guarded onExecute, without the component's cooperation, so that detection is
// exercised exactly as for a real fault. The injector (src/fault/injector) arms them at the
// scenario's times. The manifestation time is recorded on the component for the log.
// Thread-safety: arm() from any thread; fire() on the component's executor thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "keel/component.hpp"

namespace keel::runtime {

enum class InjectKind : std::uint8_t {
  None = 0,
  Segfault,        // a store to an unmapped page (SIGSEGV)
  DivideByZero,    // an integer division by zero (SIGFPE)
  Abort,           // abort() (SIGABRT)
  Throw,           // a C++ exception
  ErrorCode,       // onExecute returns InternalFault
  Hang,            // onExecute never returns (until interrupted)
  StallHeartbeat,  // the component is not executed any more (its heartbeat stops)
  OutOfRange,      // the next value pushed on a numeric output port is out of range
};

std::optional<InjectKind> parseInjectKind(std::string_view name);
std::string_view toString(InjectKind k);

/// Arms `kind` on `c` with the log's `fault_id`. OutOfRange needs `port` (an output data port
/// name, or empty for the first numeric one) and `value`. Returns false if not applicable.
bool arm(Component& c, InjectKind kind, std::uint64_t fault_id, std::string_view port = {},
         double value = 0.0);

/// Runs an armed injection; called inside the guard instead of the component's onExecute.
ReturnCode fire(Component& c, InjectKind kind);

/// steady-clock ns (the clock of every keel time).
std::int64_t steadyNs();

}  // namespace keel::runtime
