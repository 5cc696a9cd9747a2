// The machine's floors under `keel bench isolation`: what two processes on this machine cost
// with nothing of keel between them, measured in the same run and load as keel's cells.
//   floor_robust  a process blocked on a robust, process-shared mutex that another process
//                 holds: kill -9 of the holder → the blocked process running (the kernel hands
//                 the lock on, EOWNERDEAD, as it tears the holder down). The fastest any process
//                 can learn of another's death, and where keel's standby waits.
//   floor_wake    a process blocked on a futex in shared memory: the other process's store and
//                 FUTEX_WAKE → the blocked one running. What a reader that sleeps pays for any
//                 sample that crosses processes, whatever carries it.
// Each forks its processes from the calling thread (SCHED_FIFO kFifoPriority for the waiter, and
// floor_wake's waker, when `fifo`: as keel's reader and writer run); every process forked is
// reaped before it returns.
#pragma once

#include "floor.hpp"

namespace keel::bench {

/// `n` deaths, each a fresh waiter, 3 ms or more apart; the holder has `threads` threads (the
/// others asleep), as a component process has several.
FloorResult measureRobustFloor(int n, bool fifo, int threads = 1);
/// `n` wakes, 1 ms apart (as a 1 kHz stream's samples).
FloorResult measureProcessWakeFloor(int n, bool fifo);

}  // namespace keel::bench
