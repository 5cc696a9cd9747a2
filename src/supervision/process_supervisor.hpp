// keel run's side of process isolation (docs/isolation.md; decision 0011): it starts a host
// process (keel-host) per <process>, plus its standbys, and watches each one on its robust life
// lock. The death of an active host is a `process` fault of every component in it, reported to
// the fault manager through that component's proxy: keel run's stand-in for a component that
// runs elsewhere. The proxy is passive; its reset is the process's recovery (the standby that
// took over by itself, or a respawn), its stop stops the process's hosts, its emergency stop is
// the hosts' emergency stop. A standby that dies is replaced; a fresh standby is started after
// every takeover.
// Hosts are started by keel run's spawner (spawner.hpp), which outlives the supervisor.
// Thread-safety: start/stop from the engine's thread; the rest from any thread.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "keel/component.hpp"
#include "keel/result.hpp"
#include "log/fault_log.hpp"
#include "plan/plan.hpp"
#include "runtime/component_core.hpp"
#include "runtime/ipc/session.hpp"
#include "runtime/warning.hpp"
#include "supervision/spawner.hpp"

namespace keel::supervision {

/// How keel run starts a host: the executable and the arguments that make it plan the same
/// run (the profile, --set, --inject, --log); the supervisor adds the host's own.
struct HostLaunch {
  std::string executable;
  std::vector<std::string> args;
};

/// keel-host: $KEEL_HOST if set, else beside the running executable.
std::string defaultHostExecutable();

class ProcessSupervisor {
 public:
  /// `rings`: every crossing connection's memfd, by ring index (crossing.hpp); `log` gets a
  /// `host` record per host that ends; `spawner` starts every host, and outlives the supervisor.
  ProcessSupervisor(const plan::Plan& plan, runtime::ipc::Session& session,
                    std::vector<runtime::ipc::SharedMemory> rings, HostLaunch launch, runtime::Warn warn,
                    log::FaultLog& log, Spawner& spawner);
  ~ProcessSupervisor();
  ProcessSupervisor(const ProcessSupervisor&) = delete;
  ProcessSupervisor& operator=(const ProcessSupervisor&) = delete;

  /// keel run's stand-in for `instance`, which runs in a component process.
  std::unique_ptr<Component> makeProxy(const plan::PlannedInstance& instance);
  /// Where the proxies' `process` faults go (the fault manager), before launch().
  using Report = std::function<void(Component& proxy, const FaultEvent& fault)>;
  void setReport(Report report) { report_ = std::move(report); }

  /// Starts every process's active host (they load while keel run does).
  Result<void> launch();
  /// Waits until every active host runs its components, or one failed (its error, as the host
  /// reported it); then starts the standbys, in the background.
  Result<void> waitReady(std::chrono::milliseconds within);
  /// Copies of every ring's descriptor, by ring index: for keel run's own ends (Crossings).
  std::map<std::size_t, int> ringDescriptors() const;
  /// Asks every host to stop and waits for them; kills those still there after `within`.
  void stop(std::chrono::milliseconds within);

  /// Clears a latched emergency in every process (keel run's operator cleared it).
  void clearEmergency();

 private:
  struct Group;
  struct Proxy;
  friend struct Proxy;

  pid_t spawn(Group& g, std::size_t slot, bool standby, bool respawn);   // 0: failed, said in its slot
  Result<std::size_t> launchHost(Group& g, bool standby, bool respawn);  // a free slot, spawned, watched
  void watch(Group& g, std::size_t slot, pid_t pid);
  void died(Group& g, std::size_t slot, runtime::ipc::HostState was, std::int64_t t_ns, const std::string& detail);
  Result<std::int64_t> recover(Group& g);  // a proxy's reset: when the new host ran (0: not yet)
  void stopGroup(Group& g, std::chrono::milliseconds within);
  void emergency(Group& g) const;
  void topUpStandbys(Group& g);
  void queueTopUp(Group& g);  // topUpStandbys on the spawner thread, without waiting for it
  void watchBeats(Group& g);  // a thread per process with a heartbeat: kills a hung host
  Result<void> waitState(Group& g, std::size_t slot, std::chrono::milliseconds within);

  runtime::ipc::Session& session_;
  std::vector<runtime::ipc::SharedMemory> rings_;
  HostLaunch launch_;
  runtime::Warn warn_;
  log::FaultLog& log_;
  Report report_;
  std::vector<std::unique_ptr<Group>> groups_;
  std::atomic<bool> stopping_{false};
  std::vector<std::pair<Group*, std::size_t>> launched_;  // launch()'s active hosts

  // The heartbeat watchers wait on this until stop().
  std::mutex beat_mutex_;
  std::condition_variable beat_cv_;
  std::vector<std::thread> beat_watchers_;

  Spawner& spawner_;  // every host is started from it
};

}  // namespace keel::supervision
