// The machine's floor under the recovery numbers, measured in the same run and load as they
// are: what no framework on this machine can beat, and what keel's fast path avoids paying.
//   floor_wake   one thread wakes another blocked on a futex (std::atomic::wait/notify):
//                notify → the woken thread running. Every recovery that crosses a thread or a
//                process (a supervisor's message, a respawn's waitpid) pays at least this.
//   floor_timer  a thread sleeping until an absolute time (clock_nanosleep, 1 ms period):
//                the time past that moment at which it runs — the timer tick and wake-up under
//                a periodic executor's every cycle.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace keel::bench {

struct FloorResult {
  std::vector<std::int64_t> latencies_ns;
  std::string warnings;  // e.g. SCHED_FIFO refused
};

/// `n` samples, 3 ms apart (as the recovery trials are); the measured (woken, sleeping) thread
/// under SCHED_FIFO 50 when `fifo`.
FloorResult measureWakeFloor(int n, bool fifo);
FloorResult measureTimerFloor(int n, bool fifo);

}  // namespace keel::bench
