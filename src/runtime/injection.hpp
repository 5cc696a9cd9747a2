// Fault injection, the runtime side (docs/faults.md): an injection armed on a component fires
// inside its next guarded onExecute, without the component's cooperation, so that detection is
// exercised exactly as for a real fault. The injector (src/injection/injector) arms them at the
// scenario's times. The manifestation time is recorded on the component for the log.
// Thread-safety: arm() from any thread; fire() on the component's executor thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "keel/component.hpp"
#include "runtime/clock.hpp"

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
  Kill,            // SIGKILL to the component's process (components in a <process> only)
};

/// What a component standing for a whole process offers (keel run's proxy of an instance in a
/// <process>, or of a ROS 2 node): `kill` injections reach its process through it.
class ProcessTarget {
 public:
  virtual ~ProcessTarget() = default;
  /// Sends `signal` to the process now active for this component; false when there is none.
  virtual bool signalProcess(int signal) = 0;
  /// A fault stop took this component, which is in Error, so no onStop runs for it: a process
  /// that would run on by itself is ended here (a ROS 2 node's). The default ends nothing (a
  /// component process's component is in Error there too, and does nothing more).
  virtual void endProcess() {}
};

std::optional<InjectKind> parseInjectKind(std::string_view name);
std::string_view toString(InjectKind k);

struct InjectArgs {
  std::string_view port;         // OutOfRange: output data port ("" = the first numeric one)
  double value = 0.0;            // OutOfRange: the value pushed instead
  std::int64_t duration_ns = 0;  // StallHeartbeat: how long (0 = for ever)
};

/// Arms `kind` on `c` with the log's `fault_id`. StallHeartbeat and Kill take effect at once
/// (the executor skips the component; its process is killed); the others fire at its next
/// onExecute or push. Returns false if `kind` cannot apply to `c` (OutOfRange without a
/// numeric output data port, Kill on a component that is not a ProcessTarget, StallHeartbeat on
/// a component that is not Active).
bool arm(Component& c, InjectKind kind, std::uint64_t fault_id, const InjectArgs& args = {});

/// The output data port OutOfRange would corrupt, or null.
detail::OutputPortBase* corruptiblePort(Component& c, std::string_view port);

/// Runs an armed injection; called inside the guard instead of the component's onExecute.
ReturnCode fire(Component& c, InjectKind kind);

/// The component whose injected value the calling thread is pushing right now, or null: a
/// range fault found on delivery belongs to that injection.
detail::ComponentCore* injectionInFlight();

}  // namespace keel::runtime
