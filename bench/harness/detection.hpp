// keel's detection latency (detected − injected) per detector: a victim component runs on a
// 1 ms periodic executor beside a bystander, with the fault manager and the watchdog (20 ms
// heartbeat) of the runtime; each trial arms one injection (runtime::arm), waits for its
// detection, puts the victim back to Active and goes on. A hang is reported as the overshoot
// past the heartbeat timeout (the timeout itself is the integrator's choice, not a latency).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/injection.hpp"

namespace keel::bench {

/// The injections `keel bench detection` measures, each standing for a detector: the guard's
/// signals (segfault, divide_by_zero, abort), its exception and return-code checks (throw,
/// error_code), the port's range check (out_of_range) and the watchdog (hang).
inline constexpr runtime::InjectKind kDetectionKinds[] = {
    runtime::InjectKind::Segfault, runtime::InjectKind::DivideByZero, runtime::InjectKind::Abort,
    runtime::InjectKind::Throw,    runtime::InjectKind::ErrorCode,    runtime::InjectKind::OutOfRange,
    runtime::InjectKind::Hang};

/// The detector that finds an injection of `kind` ("signal", "exception", "range", ...).
std::string detectorOf(runtime::InjectKind kind);

struct DetectionCell {
  std::vector<std::int64_t> latencies_ns;  // detected − injected (hang: − the timeout)
  std::size_t failed = 0;                  // injections not detected within 5 s
  std::string warnings;                    // e.g. SCHED_FIFO not permitted
};

inline constexpr std::int64_t kDetectionHeartbeatNs = 20'000'000;

DetectionCell measureDetection(runtime::InjectKind kind, bool fifo, int n);

}  // namespace keel::bench
