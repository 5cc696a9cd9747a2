// The page `keel bench isolation` shares with its components (isolation_components.cpp): a file
// on tmpfs the harness creates and sizes, each component process maps it (its `page` property).
// The components write down what only they see — which process runs, when its first step after a
// death ended, when each sample arrived — and the harness reads it, in its own process. Every
// word is a lock-free atomic: the processes share nothing else.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>

namespace keel_bench {

/// The sample BenchStampSource sends: 64 bytes, its stamp the moment of the push.
struct Stamp {
  std::uint64_t seq = 0;
  std::int64_t t_ns = 0;  // CLOCK_MONOTONIC, taken right before the push
  std::uint64_t payload[6]{};
};

struct IsolationPage {
  static constexpr std::size_t kMaxPids = 4096;      // component processes that initialised
  static constexpr std::size_t kMaxSamples = 65536;  // port latencies kept (later ones dropped)

  // Takeover: every process whose BenchBeat initialised adds its pid; the one whose BenchBeat
  // runs sets active_pid at the end of its first onExecute, after first_ns.
  std::atomic<std::uint32_t> initialised{0};
  std::atomic<std::int32_t> active_pid{0};
  std::atomic<std::int64_t> first_ns{0};  // CLOCK_MONOTONIC: the end of the new active's first step
  std::atomic<std::uint64_t> executions{0};
  std::atomic<std::int32_t> pids[kMaxPids]{};

  // Ports: BenchStampSink stores, for each sample, its arrival − its stamp (ns).
  std::atomic<std::uint64_t> received{0};
  std::atomic<std::int64_t> latency_ns[kMaxSamples]{};
};

static_assert(std::atomic<std::int64_t>::is_always_lock_free, "the page is shared between processes");

}  // namespace keel_bench
