// keel's one clock: the steady clock (CLOCK_MONOTONIC) in ns. Every time keel keeps — fault
// detection, recovery, checkpoints, executor releases, the fault log's t_ns — is read here.
// clock_gettime is async-signal-safe, so the guard's signal handler reads the same clock, and on
// Linux it is a vDSO call (no system call), cheap enough for every callback.
// Thread-safety: any thread, and inside a signal handler.
#pragma once

#include <time.h>

#include <cstdint>

namespace keel::runtime {

inline std::int64_t steadyNs() noexcept {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace keel::runtime
