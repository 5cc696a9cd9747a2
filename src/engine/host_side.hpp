// A component process's side of the engine (side.hpp; keel-host, src/host): it joins the run's
// log and session, and runs the instances of its <process> once it holds the process's role:
// at once when it starts active, or — a standby — when the active process dies, on the thread
// of its task that runs first, so that the takeover costs no second wake-up. Until its
// components run, their `state` records wait (no JSON on the takeover's way).
// Thread-safety: as Side's; standBy()/leaveRole() on the role executor's thread.
#pragma once

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "engine/side.hpp"
#include "runtime/alarm.hpp"
#include "runtime/executor.hpp"
#include "supervision/process_host.hpp"

namespace keel::engine {

class Engine;

class HostSide final : public Side {
 public:
  HostSide(Engine& engine, supervision::ProcessHost& host);
  ~HostSide() override = default;
  HostSide(const HostSide&) = delete;
  HostSide& operator=(const HostSide&) = delete;

  const std::string& process() const override { return host_.role().process; }
  Result<void> openLog() override;
  Result<void> setUpProcesses() override;
  std::unique_ptr<Component> standIn(const plan::PlannedInstance&) override { return nullptr; }
  void adopt(const plan::PlannedInstance& pi, detail::ComponentCore& core) override;
  runtime::ipc::Session& session() override { return host_.session(); }
  std::map<std::size_t, int> ringDescriptors() override { return host_.takeRingDescriptors(); }
  bool publishesDiagnostics() const override { return false; }
  bool joinsRosGraph() const override { return false; }
  dds::GraphWatch* graphWatch() override { return nullptr; }
  bool quiet(std::string_view) const override { return false; }
  bool standingBy() const override { return host_.role().standby; }
  bool injects(const injection::ScheduledFault& f, const plan::PlannedInstance* pi) const override;
  Result<void> launch() override;
  Result<void> waitReady() override { return {}; }
  Result<void> run() override;
  bool holdsState(const Component& c, State from, State to) override;
  void stateLogged(std::string_view) override {}
  void emergencyCleared() override {}
  void stopProcesses() override {}
  void stopped() override {}
  void close() override;

 private:
  /// How this process came to run its components: its `host` record's phase (null: stopped
  /// while standing by) and how many checkpoints it restored. The record is made and written
  /// once the components run (a JSON object costs ~12 µs, which the takeover does not wait for).
  struct RoleTaken {
    const char* phase = nullptr;
    std::size_t restored = 0;
  };
  /// The executors made and parked, the role taken (by the main thread, or a standby's by its
  /// first task's thread: standBy), the components running.
  Result<RoleTaken> start();
  /// The role lock (a standby sleeps here), a takeover's restore, the rings.
  Result<RoleTaken> takeRole();
  /// A standby's executor that takes the role (the task that runs first); null without any.
  runtime::Executor* roleExecutor() const;
  /// On `self`'s thread, before it parks: takes the role, and runs the components if it is
  /// theirs; the main thread waits for the outcome (role_settled_).
  void standBy(runtime::Executor& self);
  /// On `self`'s thread, as it ends: releases the role if it holds it (see process_host.hpp).
  void leaveRole(const runtime::Executor& self) const;
  /// The calling thread at the highest real-time priority of the process's tasks (none:
  /// unchanged).
  void raiseToProcessPriority();

  Engine& e_;
  supervision::ProcessHost& host_;
  std::unique_ptr<supervision::HostFaultSink> sink_;
  std::string tee_error_;  // the tee could not be opened: said once the log is shared

  std::optional<Result<RoleTaken>> role_taken_;  // a standby's, set on its role executor's thread
  std::atomic<std::uint32_t> role_settled_{0};   // 1 once role_taken_ is set
  runtime::Alarm role_alarm_;                    // wakes the main thread once the role is settled
  /// How long the main thread of a standby that took over waits for the first cycle at most.
  static constexpr std::chrono::milliseconds kFirstStepWait{20};

  std::mutex held_mutex_;      // guards the two below (any component's thread)
  bool hold_records_ = false;  // a takeover under way: state records wait, in order
  struct HeldState {           // a state record to write (no JSON made on the takeover's way)
    const Component* component;
    State from, to;
    std::int64_t t;
  };
  std::vector<HeldState> held_;  // written once the components run
};

}  // namespace keel::engine
