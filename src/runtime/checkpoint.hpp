// Checkpoints of a component's critical() memory (paper §5.3.1): copies taken on the
// component's own thread between its callbacks (so a copy is never torn), at start and then
// every <checkpoint period>; restored into the component on reset, or into its replacement.
// Thread-safety: take() on the component's thread (no callback of it running); restore() on
// that thread too; copyInto() from any thread (the copy is guarded by the core's mutex).
#pragma once

#include <cstdint>

#include "runtime/component_core.hpp"

namespace keel::runtime {

/// Takes a checkpoint now (allocating its buffers on the first call, or when a region grew).
void takeCheckpoint(detail::ComponentCore& core, std::int64_t now_ns);

/// Takes a checkpoint when the period has elapsed (cheap otherwise: one comparison).
inline void checkpointIfDue(detail::ComponentCore& core, std::int64_t now_ns) {
  if (core.checkpoints.period_ns != 0 && now_ns >= core.checkpoints.next_ns && !core.critical.empty())
    takeCheckpoint(core, now_ns);
}

/// Copies the last checkpoint back into the component's critical memory. Returns when that
/// checkpoint was taken (steady ns), or 0 when there is none (nothing registered or never
/// taken); the memory is then left as it is.
std::int64_t restoreCheckpoint(detail::ComponentCore& core);

/// In a component process taking over (or respawned): loads the checkpoint the process before
/// it published in shared memory (CheckpointStore::shared), then restores it as above. 0 when
/// there is none, or it has other regions than this component registered.
std::int64_t restoreSharedCheckpoint(detail::ComponentCore& core);

/// Allocates the checkpoint's buffers now (a standby host, before it waits: a takeover then
/// allocates nothing on its way to the first step).
void reserveCheckpoint(detail::ComponentCore& core);

/// Copies `from`'s last checkpoint into `to`'s critical memory, region by region in the order
/// they were registered, each up to the shorter length. Returns how many regions were copied.
std::size_t copyCheckpoint(detail::ComponentCore& from, detail::ComponentCore& to);

}  // namespace keel::runtime
