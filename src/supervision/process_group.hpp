// The supervisor's bookkeeping of one <process> (process_supervisor.hpp): its hosts' slots,
// their watchers, the proxies of its instances; and the waits on its block of the session.
// Private to the supervisor's files (process_supervisor.cpp, process_recovery.cpp).
// Thread-safety: Group's slot bookkeeping under its mutex; the block's fields are atomics.
#pragma once

#include <fmt/format.h>
#include <signal.h>

#include <array>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "runtime/futex.hpp"
#include "runtime/injection.hpp"
#include "supervision/process_supervisor.hpp"

namespace keel::supervision {

inline runtime::ipc::HostState stateOf(const runtime::ipc::HostSlot& s) {
  return static_cast<runtime::ipc::HostState>(s.state.load(std::memory_order_acquire));
}

/// Waits until `done()` or `deadline`, waking at each change in `block` (every host state,
/// first cycle, emergency done and slot freed bumps `changes`); what `done()` said last.
template <class Done>
bool waitFor(runtime::ipc::ProcessBlock& block, std::chrono::steady_clock::time_point deadline, Done done) {
  for (;;) {
    const std::uint32_t seen = block.changes.load(std::memory_order_acquire);
    if (done()) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    runtime::futexWait(block.changes, seen, &deadline, runtime::FutexScope::Shared);
  }
}

inline pid_t activePid(const runtime::ipc::ProcessBlock& block) {
  for (const auto& s : block.slots)
    if (stateOf(s) == runtime::ipc::HostState::Active) return s.pid.load(std::memory_order_acquire);
  return 0;
}

struct ProcessSupervisor::Group {
  const plan::PlannedProcess* plan = nullptr;
  std::size_t index = 0;
  runtime::ipc::ProcessBlock* block = nullptr;
  std::vector<std::size_t> rings;  // ring indices its hosts read or write
  std::vector<Proxy*> proxies;
  bool takes_over = false;  // every member's `process` faults are reset: standbys take over by themselves
  int standby = 0;          // standbys to keep ready

  mutable std::mutex mutex;       // guards the slots' bookkeeping below
  std::int64_t heartbeat_ns = 0;  // the process's (processHeartbeatNs); 0: not watched
  std::array<pid_t, runtime::ipc::kHostSlots> pids{};
  std::array<std::string, runtime::ipc::kHostSlots> hung{};  // why a host was killed as hung
  std::array<bool, runtime::ipc::kHostSlots> used{};
  struct Watcher {
    std::thread thread;
    std::shared_ptr<std::atomic<bool>> done;  // its host died and it reported it
  };
  std::vector<Watcher> watchers;  // finished ones are joined when the next host starts
  std::mutex recover_mutex;       // one recovery at a time
  std::atomic<bool> stopped{false};
};

struct ProcessSupervisor::Proxy final : Component, runtime::ProcessTarget {
  Proxy(ProcessSupervisor& s, Group& g) : sup(s), group(g) {}
  ReturnCode onReset() override {
    auto r = sup.recover(group);
    if (r) {
      runtime::coreOf(*this).fault.recovered_at_ns.store(*r, std::memory_order_release);
      return ReturnCode::Ok;
    }
    sup.warn_(fmt::format("process '{}': {}", group.plan->name, r.error().message));
    return ReturnCode::InternalFault;
  }
  ReturnCode onStop() override {
    sup.stopGroup(group, std::chrono::seconds(2));
    return ReturnCode::Ok;
  }
  ReturnCode onEmergencyStop() override {
    sup.emergency(group);
    return ReturnCode::Ok;
  }
  bool signalProcess(int signal) override {
    const pid_t pid = activePid(*group.block);
    return pid > 0 && ::kill(pid, signal) == 0;
  }
  ProcessSupervisor& sup;
  Group& group;
};

}  // namespace keel::supervision
