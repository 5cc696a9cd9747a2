// The peers a user would otherwise choose, measured in the same run as keel and in the same
// terms: the time from the crash to the replacement ready to work.
//   erlang   an Erlang/OTP `one_for_one` supervisor restarting a gen_server that crashed
//            (badarith) — Debian's erlang-base; compiled from share/keel/bench/peers at run time
//   respawn  a supervisor process that respawns (posix_spawn) a child killed by SIGSEGV, as
//            systemd's Restart=always or a launch file's respawn=true do
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

}  // namespace keel::bench
