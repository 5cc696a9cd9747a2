// A component process's side of process isolation (docs/isolation.md; decision 0011): what
// keel-host (src/host) does around the engine that runs its components.
// - Life: its main thread takes the slot's robust life lock first thing (keel run's watcher
//   sleeps on it: the host's death wakes it), and never exits while the process lives.
// - Role: the active host holds the process's role lock; a standby sleeps on it, loaded and
//   initialised, and the kernel wakes one standby when the active dies. That one restores the
//   checkpoints, takes the rings over and runs. A host started as the active (or respawned)
//   takes it on its main thread; a standby on the thread of the task that runs first, so that
//   the thread the kernel wakes is the one that runs the component (no second wake). A role
//   held by such a thread is released by that thread when it ends at a stop; should it end
//   otherwise (abandoned in a hung callback, and back), it parks until the process ends: its
//   release would tell the standbys the process died (runtime/ipc/robust_mutex.hpp's rule).
// - No orphans: a watcher thread sleeps on keel run's supervisor lock; if keel run dies, it runs
//   the emergency stop of the components it hosts and exits the process, its log lines whole. PR_SET_PDEATHSIG
//   (SIGTERM) is the backstop, checked with getppid() against the parent keel run named.
// - Commands from keel run (stop, emergency, clear) arrive on the process block's command word.
// Thread-safety: enter/serve/leave on the main thread; takeRole/releaseRole on the thread that
// holds the role (one at a time); the rest is its own threads'.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "keel/result.hpp"
#include "log/fault_log.hpp"
#include "plan/plan.hpp"
#include "runtime/component_core.hpp"
#include "runtime/ipc/session.hpp"

namespace keel::supervision {

/// A host's exit status when keel run died (after the emergency stop of what it hosts), and
/// when a standby took over the rings it writes (it was declared dead: it leaves at once).
inline constexpr int kExitSupervisorLost = 70;
inline constexpr int kExitFenced = 71;

/// What keel run tells a host on its command line.
struct HostRole {
  std::string process;                  // the <process> it runs
  std::size_t slot = 0;                 // its slot in the process block
  bool standby = false;                 // wait to take over
  bool respawn = false;                 // a replacement for a dead active: restore the checkpoints
  int session_fd = -1;                  // the session region (owned by the host from here)
  std::map<std::size_t, int> ring_fds;  // by ring index
  pid_t parent = 0;                     // keel run
};

/// The session's shape for `plan` (what its indices index), as keel run and every host make it.
runtime::ipc::SessionShape sessionShape(const plan::Plan& plan);
/// The heartbeat timeout of `process` as a whole: the shortest <heartbeat timeout> of its
/// components' policies (0: none, the process is not watched for hangs).
std::int64_t processHeartbeatNs(const plan::Plan& plan, std::string_view process);

/// How many processes write the run's log (stages in the session's log arena).
inline std::size_t logParticipants(const plan::Plan& plan) {
  return 1 + plan.processes.size() * runtime::ipc::kHostSlots;
}

/// The checkpoint index of `instance` in the session (instances in processes, in plan order).
std::optional<std::size_t> checkpointIndex(const plan::Plan& plan, std::string_view instance);

class ProcessHost {
 public:
  /// Maps the session keel run handed over and checks it was made for `plan`.
  static Result<std::unique_ptr<ProcessHost>> open(const plan::Plan& plan, HostRole role);
  /// Beats every `period` once active (keel run kills a process whose beat stops: a hang).
  void setHeartbeat(std::int64_t period_ns) { beat_period_ns_ = period_ns; }
  ~ProcessHost();
  ProcessHost(const ProcessHost&) = delete;
  ProcessHost& operator=(const ProcessHost&) = delete;

  /// Main thread, first: takes the life lock, says Loading, starts watching keel run.
  /// `supervisor_lost` runs on the watcher thread if keel run dies, before the process exits.
  Result<void> enter(std::function<void()> supervisor_lost);
  /// The run's log as this host's engine writes it (null: none, or no more). If keel run
  /// dies, before the host exits, whatever its role: keel run's unfinished line is written
  /// again, and the host's own line in flight is finished (FaultLog::quiesce), so that the
  /// lines the others write on leave no hole of a line never written.
  void setLog(log::FaultLog* log);
  /// The host could not start: `message` goes to keel run, which prints it.
  void failed(const std::string& message);
  /// The active takes the role lock; a standby says Standby and sleeps on it. True when its last
  /// holder died (a takeover, or a respawn after a death); false when it was released (keel run
  /// is stopping the process: check stopRequested()). The calling thread holds the role until
  /// releaseRole(), and must not end before (the main thread, or see the header's "Role").
  Result<bool> takeRole();
  /// Releases the role if the calling thread holds it (leave() does, for the main thread).
  void releaseRole();
  bool holdsRole() const;
  bool stopRequested();
  /// Whether a host of this process found keel run gone (it then stopped the actuators and
  /// left); read after takeRole: a standby must not take over a run that is over.
  bool runLost() { return block().supervisor_lost.load(std::memory_order_acquire) != 0; }
  /// keel run died: the emergency stop once (by the active host), then _exit.
  [[noreturn]] void supervisorLost();
  /// The components run: says Active.
  void becameActive();
  /// The first successful cycle after becoming active.
  void ranOnce(std::int64_t t_ns);
  /// Main thread: serves keel run's commands until a stop (or SIGTERM/SIGINT). `emergency`
  /// and `clear` run the engine's emergency stop and its clearing.
  void serve(const std::function<void()>& emergency, const std::function<void()>& clear);
  /// Main thread, last: releases the role, says Exited, releases the life lock.
  void leave();

  runtime::ipc::Session& session() { return session_; }
  const HostRole& role() const { return role_; }
  /// The rings' descriptors keel run handed over, by ring index (the caller owns them now).
  std::map<std::size_t, int> takeRingDescriptors() { return std::exchange(role_.ring_fds, {}); }
  std::size_t processIndex() const { return index_; }

 private:
  ProcessHost(runtime::ipc::Session session, HostRole role, std::size_t index);
  runtime::ipc::ProcessBlock& block() { return session_.process(index_); }
  runtime::ipc::HostSlot& slot() { return block().slots[role_.slot]; }

  runtime::ipc::Session session_;
  HostRole role_;
  std::size_t index_;
  [[noreturn]] void exitLeavingLogWhole(int status);

  std::function<void()> supervisor_lost_;
  std::once_flag lost_once_;
  std::mutex log_mutex_;  // held from an exit's start to its end: the log is not destroyed meanwhile
  log::FaultLog* log_ = nullptr;
  std::atomic<pid_t> role_tid_{0};  // the thread holding the role lock (0: none)
  bool has_life_ = false;
  std::atomic<bool> active_{false};
  std::atomic<bool> signalled_{false};  // SIGTERM/SIGINT: stop
  std::thread supervisor_watcher_;
  std::thread signal_watcher_;
  std::thread beat_;  // while active, when the process has a heartbeat
  std::int64_t beat_period_ns_ = 0;
};

/// A host's components report here: their first good cycle after the host became active is
/// the process's `ranOnce` (keel run's `recovered` moment of a takeover); every other report
/// goes on to the fault manager.
class HostFaultSink final : public runtime::FaultSink {
 public:
  static constexpr std::uint64_t kFirstRun = ~std::uint64_t{0};  // a recovering_id no fault has
  HostFaultSink(runtime::FaultSink& manager, ProcessHost& host) : manager_(manager), host_(host) {}
  void report(Component& c, const FaultEvent& fault) override { manager_.report(c, fault); }
  void reportFailedTransition(Component& c, const FaultEvent& fault) override {
    manager_.reportFailedTransition(c, fault);
  }
  void runPending(Component& c) override { manager_.runPending(c); }
  void recovered(Component& c, std::int64_t t_ns) override;

 private:
  runtime::FaultSink& manager_;
  ProcessHost& host_;
};

}  // namespace keel::supervision
