// The machine's floor under the recovery numbers, measured in the same run and load as they
// are: what no framework on this machine can beat, and what keel's fast path avoids paying.
//   floor_wake   one thread wakes another blocked on a futex (std::atomic::wait/notify):
//                notify → the woken thread running. Every recovery that crosses a thread or a
//                process (a supervisor's message, a respawn's waitpid) pays at least this.
//   floor_timer  a thread sleeping until an absolute time (clock_nanosleep, 1 ms period):
//                the time past that moment at which it runs — the timer tick and wake-up under
//                a periodic executor's every cycle.
// And under the detection numbers (`keel bench detection`), the same faults caught with nothing
// of keel, striking as keel's detection trials do (a thread on a 1 ms absolute-time cycle faults
// every third cycle, right after it wakes):
//   floor_signal a store to an unmapped page caught by a bare SA_SIGINFO handler on an
//                alternate stack, which takes the time and siglongjmps back: the kernel's
//                delivery of SIGSEGV, which keel's guard pays as well.
//   floor_throw  a std::runtime_error thrown and caught one frame up: the C++ unwinder.
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
/// `n` faults caught, fault → caught, one every `every` cycles (3: as keel's detection trials;
/// 1: on every cycle, the path kept warm). measureSignalFloor replaces the process's SIGSEGV
/// action while it runs (and puts it back): no other thread may fault meanwhile.
FloorResult measureSignalFloor(int n, bool fifo, int every = 3);
FloorResult measureThrowFloor(int n, bool fifo, int every = 3);

}  // namespace keel::bench
