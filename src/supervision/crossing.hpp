// Connections between processes (docs/isolation.md, "Ports across processes"). Each data or
// event connection whose two ends run in different processes goes through a ring
// (runtime/ipc/ring.hpp) in a memfd that keel run creates empty: the process of the output port
// sizes it (it knows sizeof(T)) and writes into it through an outlet attached to that port; the
// process of the input port waits for it to be laid out, then reads it on the executor of the
// input's component (runtime::ExternalInput: the executor sleeps on the ring and drains it
// before its members run) — or, for a component without one or a kernel without futex_waitv,
// on a pump thread of its own — delivering each value into the input port as an in-process
// connection would (its queue policy, its validity rule). One copy into the ring, one out of
// it; one wake from the writer's push to the reader's step.
// A writer whose ring was taken over (a standby became the active) is refused its next push: it
// was fenced, and the host it runs in exits at once (never two writers).
// Thread-safety: connect/attach/takeOver/resume/start/stop from the engine's thread (a standby
// host's takeOver/resume from the thread that took the role, while the engine's waits for it);
// pushes from the output's component thread; a ring is read on its executor's thread or its
// pump's.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "keel/component.hpp"
#include "keel/result.hpp"
#include "plan/plan.hpp"
#include "runtime/ipc/ring.hpp"
#include "runtime/ipc/session.hpp"
#include "runtime/warning.hpp"
#include "runtime/wire.hpp"

namespace keel::supervision {

/// The data and event connections of `plan` whose ends run in different processes, as indices
/// into plan.connections: index i of this list is the connection's ring index in the session.
std::vector<std::size_t> crossingConnections(const plan::Plan& plan);

/// The ring's slot count for a connection: the input queue's size, rounded up to a power of
/// two, at least 64 (the reader drains the ring into the queue, which applies the policy).
std::size_t ringSlots(const plan::Plan& plan, const plan::PlannedConnection& c);

/// Why `port` (one end of the crossing connection `c`) cannot cross processes, as
/// `file:line: message`, or nothing: values cross as bytes, so a type that is not trivially
/// copyable (a std::string inside) cannot. A component process refuses such a connection when
/// it connects; keel validate --load, which loads every process's code, at load.
std::optional<std::string> crossingProblem(const plan::Plan& plan, const plan::PlannedConnection& c,
                                           const detail::PortBase& port);

class Crossings {
 public:
  using Find = std::function<Component*(std::string_view instance)>;
  using Fenced = std::function<void()>;  // this process's writer was fenced by a takeover

  Crossings();
  ~Crossings();
  Crossings(const Crossings&) = delete;
  Crossings& operator=(const Crossings&) = delete;

  /// Sets up this process's ends of the crossing connections: `process` is this process's
  /// name (empty: keel run), `fds` each ring's memfd by ring index (owned from here). Writers are
  /// attached (not yet writing: takeOver); readers wait up to `wait` for their ring to be laid
  /// out, then read it once start() is called. Errors name the connection's file:line.
  Result<void> connect(const plan::Plan& plan, const std::string& process, runtime::ipc::Session& session,
                       std::map<std::size_t, int> fds, const Find& find, std::chrono::milliseconds wait,
                       const Fenced& fenced, const runtime::Warn& warn);
  /// Makes this process the writer of every ring it writes (at its start, or at a takeover).
  Result<void> takeOver();
  /// Hands each reader to the executor of its component, which reads it from its start on
  /// (after connect() and the executors' construction, before they start).
  void attach();
  /// Each reader resumes where the process before it stopped reading (before its executor or
  /// pump starts: at the start, or at a takeover).
  void resume();
  /// Starts a pump thread for each reader no executor reads (after the executors start).
  void start();
  /// Stops and joins the pumps; writers stay attached (a late push is harmless). Readers read
  /// by an executor stop with it.
  void stop();

  /// The in-process connections behind the ends (the ring's side has no port), for a
  /// component's replacement.
  std::vector<runtime::Wire> wires() const;

  /// Values a reader lost because it fell a whole ring behind.
  std::uint64_t dropped() const;

 private:
  struct Writer;
  struct Reader;
  std::vector<std::unique_ptr<Writer>> writers_;
  std::vector<std::unique_ptr<Reader>> readers_;
};

}  // namespace keel::supervision
