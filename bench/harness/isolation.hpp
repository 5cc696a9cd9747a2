// `keel bench isolation`: components in processes of their own (docs/isolation.md), measured as
// a user runs them — `keel run` started by the harness on profiles it writes, over the
// benchmark's components (bench/components/isolation_components.cpp), which note what they see
// in a page shared with the harness (bench_page.hpp):
//   takeover      kill -9 of the active process of `<process standby="1">` → the end of the first
//                 onExecute of the standby that took over (restoring 4 KB of checkpoint)
//   respawn       the same with standby="0": keel run respawns the process, cold
//   port_process  a 64-byte sample pushed in a component process → the reading component
//                 (aperiodic, in keel run's process) running with it: one way, 1 kHz
//   port_thread   the same two components in one process: keel's in-process port
//   standby cost  CPU and memory of a waiting standby beside its active process
// The floors and the DDS peer beside them are process_floor.hpp's and peers.hpp's.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "paths.hpp"

namespace keel::bench {

struct IsolationCell {
  std::vector<std::int64_t> latencies_ns;
  std::size_t failed = 0;      // trials that did not end within their bound
  std::size_t unexpected = 0;  // takeover trials that were respawns (no standby was ready)
  std::string error;           // non-empty: the cell could not run
  std::string warnings;
  int host_threads = 0;                           // takeover: the threads of the active component process
  std::vector<std::int64_t> detected_to_step_ns;  // takeover: the fault log's recovered − detected
};

/// `n` kills of the active process (one warm-up kill first); `standby`: one standby (takeover),
/// else none (respawn). `fifo`: the component's task under SCHED_FIFO kFifoPriority. Every n/10
/// kills, `between(n/10, threads)` runs, `threads` those of the active process (the floor,
/// interleaved so that the machine's drift weighs alike).
IsolationCell measureTakeover(const Paths& paths, bool standby, bool fifo, int n,
                              const std::function<void(int, int)>& between = {});
/// `n` samples at 1 kHz from a writer to an aperiodic reader; `crossing`: the writer in a
/// component process, else both in keel run's.
IsolationCell measurePort(const Paths& paths, bool crossing, bool fifo, int n);

/// A standby beside its active, over `seconds` with both loaded and ready.
struct StandbyCost {
  std::string error;
  double seconds = 0;
  long active_cpu_ticks = 0, standby_cpu_ticks = 0;  // utime + stime of every thread, in ticks
  long active_switches = 0, standby_switches = 0;    // context switches of every thread
  long active_rss_kb = 0, standby_rss_kb = 0;
  long active_pss_kb = 0, standby_pss_kb = 0;  // shared pages split among their users
  // Resident anonymous memory (heap, stacks, data written): what a process costs of its own, as
  // against the code and libraries' pages, resident as far as each process happened to touch them.
  long active_anon_kb = 0, standby_anon_kb = 0;
  int tick_hz = 100;
};
StandbyCost measureStandbyCost(const Paths& paths, double seconds);

}  // namespace keel::bench
