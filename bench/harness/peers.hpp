// The peers a user would otherwise choose, measured in the same run as keel and in the same
// terms: the time from the crash to the replacement ready to work.
//   erlang   an Erlang/OTP `one_for_one` supervisor restarting a gen_server that crashed
//            (badarith) — Debian's erlang-base; compiled from share/keel/bench/peers at run time
//   respawn  a supervisor process that respawns (posix_spawn) a child killed by SIGSEGV, as
//            systemd's Restart=always or a launch file's respawn=true do
//   dds      for ports (`keel bench isolation`): CycloneDDS's own `ddsperf` (Debian's
//            cyclonedds-tools) ping/pong on the loopback interface, 64-byte samples at 1 kHz,
//            a WaitSet on each side — raw DDS between two processes, no ROS above it
// Each returns one latency per fault, or why it could not run here (the table says so).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "paths.hpp"

namespace keel::bench {

struct PeerResult {
  std::vector<std::int64_t> latencies_ns;  // crash → replacement ready, one per recovered fault
  std::size_t failed = 0;                  // faults not recovered within the bound
  std::string skipped;                     // non-empty: did not run, and why
  std::string detail;                      // what ran, when it says (erlang: "OTP 25")
};

/// `n` faults; `fifo`: the peer runs under SCHED_FIFO priority 50 (skipped when not permitted).
PeerResult runErlangPeer(const Paths& paths, int n, bool fifo);
PeerResult runRespawnPeer(const Paths& paths, int n, bool fifo);

/// ddsperf reports percentiles per second, not samples: its one-way latency is the round trip
/// ÷ 2, p50 the median of the seconds' medians, p99 the median of their 99th percentiles.
struct DdsResult {
  std::size_t samples = 0;  // round trips over the counted seconds
  double p50_us = 0, p99_us = 0, max_us = 0;
  std::string skipped;  // non-empty: did not run, and why
  std::string detail;   // ddsperf's version line
};
/// About `n` round trips (at least 5 s of them, the first second dropped).
DdsResult runDdsPeer(int n, bool fifo);

}  // namespace keel::bench
