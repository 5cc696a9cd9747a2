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

#include <signal.h>

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
inline constexpr int kDetectionCadence = 3;  // a fault every third cycle, as keel's trials strike
FloorResult measureSignalFloor(int n, bool fifo, int every = kDetectionCadence);
FloorResult measureThrowFloor(int n, bool fifo, int every = kDetectionCadence);

/// One trial of each floor, for benchmarks that interleave them with keel's (signal_floor.cpp).
/// While a BareSegvHandler lives, the process's SIGSEGV goes to the floor's bare handler (it
/// takes the time and jumps back) instead of keel's, which is put back after; no other thread
/// may fault meanwhile.
class BareSegvHandler {
 public:
  BareSegvHandler();
  ~BareSegvHandler();
  BareSegvHandler(const BareSegvHandler&) = delete;
  BareSegvHandler& operator=(const BareSegvHandler&) = delete;

 private:
  struct sigaction saved_ {};
};
/// A store to page 0 under a BareSegvHandler on a thread with an alternate stack: fault →
/// caught, ns.
std::int64_t bareSegfault();
/// A std::runtime_error thrown and caught one frame up: throw → caught, ns.
std::int64_t bareThrow();
/// The faults themselves, out of line (a store to page 0; a std::runtime_error), for keel's side.
[[gnu::noinline]] void storeToPageZero();
[[gnu::noinline]] void throwRuntimeError();

}  // namespace keel::bench
