// The supervisor's handling of a <process> once it runs (process_supervisor.hpp): its recovery
// after its active host died (the standby that took over, or a respawn), its standbys kept
// ready, its emergency stop and fault stop, and the heartbeat watch that kills a hung host.
#include <fmt/format.h>
#include <signal.h>

#include <optional>

#include "runtime/clock.hpp"
#include "supervision/process_group.hpp"

namespace keel::supervision {
namespace {

namespace ipc = runtime::ipc;
using ipc::HostState;
using Clock = std::chrono::steady_clock;
constexpr auto kTakeoverWait = std::chrono::seconds(2);  // for a standby that is taking over
constexpr auto kRespawnWait = std::chrono::seconds(10);  // for a respawned host to run
constexpr auto kFirstRunWait = std::chrono::seconds(1);  // for the new active's first cycle
constexpr auto kEmergencyWait = std::chrono::seconds(1);

}  // namespace

void ProcessSupervisor::watchBeats(Group& g) {
  const auto period = std::chrono::nanoseconds(g.heartbeat_ns / 4);
  std::unique_lock lock(beat_mutex_);
  while (!beat_cv_.wait_for(lock, period, [this] { return stopping_.load(std::memory_order_acquire); })) {
    if (g.stopped.load(std::memory_order_acquire)) continue;
    const std::int64_t now = runtime::steadyNs();
    std::lock_guard slots(g.mutex);
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i) {
      const ipc::HostSlot& s = g.block->slots[i];
      if (!g.used[i] || g.pids[i] <= 0 || stateOf(s) != HostState::Active || !g.hung[i].empty()) continue;
      const std::int64_t silent = now - s.beat_ns.load(std::memory_order_acquire);
      if (silent <= g.heartbeat_ns) continue;
      // Killed before anyone else writes its ports: its standby takes over from a dead writer.
      g.hung[i] = fmt::format("hung: no heartbeat for {:.1f} ms (heartbeat timeout {:.1f} ms), killed", silent / 1e6,
                              g.heartbeat_ns / 1e6);
      ::kill(g.pids[i], SIGKILL);
    }
  }
}

void ProcessSupervisor::topUpStandbys(Group& g) {
  if (stopping_.load(std::memory_order_acquire) || g.stopped.load(std::memory_order_acquire)) return;
  int have = 0;
  {
    std::lock_guard lock(g.mutex);
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i) {
      if (!g.used[i]) continue;
      const HostState st = stateOf(g.block->slots[i]);
      have += st == HostState::Starting || st == HostState::Loading || st == HostState::Standby;
    }
  }
  for (; have < g.standby; ++have)
    if (auto r = launchHost(g, true, false); !r) warn_(r.error().message);
}

Result<std::int64_t> ProcessSupervisor::recover(Group& g) {
  std::lock_guard recovering(g.recover_mutex);
  // The dead host's slot says Failed by now (died()), and only one host holds the role: a slot
  // that says Active is the standby that took over (perhaps before keel run saw the death).
  auto newActive = [&]() -> std::optional<std::size_t> {
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i)
      if (stateOf(g.block->slots[i]) == HostState::Active) return i;
    return std::nullopt;
  };
  auto standbyLeft = [&] {
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i)
      if (stateOf(g.block->slots[i]) == HostState::Standby) return true;
    return false;
  };
  std::optional<std::size_t> active = newActive();
  if (!active && g.takes_over)  // a standby is taking over by itself, unless it died too
    waitFor(*g.block, Clock::now() + kTakeoverWait, [&] { return (active = newActive()) || !standbyLeft(); });
  if (!active) {  // no standby: a new host, which restores the checkpoint too
    auto slot = launchHost(g, false, true);
    if (!slot) return slot.error();
    if (auto r = waitState(g, *slot, kRespawnWait); !r) return fail("respawn failed: " + r.error().message);
    active = *slot;
  }
  // Back once the new active's components ran a cycle (bounded: an aperiodic one may wait).
  const ipc::HostSlot& s = g.block->slots[*active];
  waitFor(*g.block, Clock::now() + kFirstRunWait, [&] { return s.first_run_ns.load(std::memory_order_acquire) != 0; });
  queueTopUp(g);
  return s.first_run_ns.load(std::memory_order_acquire);
}

void ProcessSupervisor::queueTopUp(Group& g) {
  spawner_.post([this, &g] { topUpStandbys(g); });
}

void ProcessSupervisor::emergency(Group& g) const {
  const std::uint32_t before = g.block->emergencies_done.load(std::memory_order_acquire);
  ipc::publishCommand(*g.block, ipc::Command::Emergency);
  waitFor(*g.block, Clock::now() + kEmergencyWait, [&] {
    return g.block->emergencies_done.load(std::memory_order_acquire) != before || activePid(*g.block) == 0;
  });
}

void ProcessSupervisor::clearEmergency() {
  for (auto& g : groups_)
    if (g->block->command.load(std::memory_order_acquire) == static_cast<std::uint32_t>(ipc::Command::Emergency))
      ipc::publishCommand(*g->block, ipc::Command::Run);
}

void ProcessSupervisor::stopGroup(Group& g, std::chrono::milliseconds within) {
  if (g.stopped.exchange(true)) return;
  ipc::publishCommand(*g.block, ipc::Command::Stop);
  auto alive = [&] {
    std::lock_guard lock(g.mutex);
    for (bool u : g.used)
      if (u) return true;
    return false;
  };
  waitFor(*g.block, Clock::now() + within, [&] { return !alive(); });
  {
    std::lock_guard lock(g.mutex);
    for (std::size_t i = 0; i < ipc::kHostSlots; ++i)
      if (g.used[i] && g.pids[i] > 0) {
        warn_(fmt::format("process '{}': host {} did not stop within {} ms; killed", g.plan->name, g.pids[i],
                          within.count()));
        ::kill(g.pids[i], SIGKILL);
      }
  }
}

}  // namespace keel::supervision
