// The page `keel bench` shares with its components (isolation_components.cpp, dds_components.cpp):
// a file on tmpfs the harness creates and sizes (bench_run.hpp), which each component process maps
// (its `page` property). The components write down what only they see — which process runs, when
// its first step after a death ended, when each sample arrived, whose sample it was — and the
// harness reads it, in its own process. Every word is a lock-free atomic: the processes share
// nothing else.
#pragma once

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <ctime>
#include <string>

namespace keel_bench {

/// The sample BenchStampSource sends: 64 bytes, its stamp the moment of the push.
struct Stamp {
  std::uint64_t seq = 0;
  std::int64_t t_ns = 0;  // CLOCK_MONOTONIC, taken right before the push
  std::uint64_t payload[6]{};
};

struct BenchPage {
  static constexpr std::size_t kMaxPids = 4096;      // component processes that initialised
  static constexpr std::size_t kMaxSamples = 65536;  // port latencies kept (later ones dropped)

  // Takeover: every process whose BenchBeat initialised adds its pid; the one whose BenchBeat
  // runs sets active_pid at the end of its first onExecute, after first_ns.
  // DDS failover: BenchDdsSink sets active_pid to the writer whose sample it takes when that
  // writer is not the last one's, after first_ns (that sample's arrival).
  std::atomic<std::uint32_t> initialised{0};
  std::atomic<std::int32_t> active_pid{0};
  std::atomic<std::int64_t> first_ns{0};  // CLOCK_MONOTONIC
  std::atomic<std::uint64_t> executions{0};
  std::atomic<std::int32_t> pids[kMaxPids]{};

  // Ports: a sink stores, for each sample, its arrival − its stamp (ns): one way for
  // BenchStampSink, the round trip for BenchDdsSink.
  std::atomic<std::uint64_t> received{0};
  std::atomic<std::int64_t> latency_ns[kMaxSamples]{};
};

static_assert(std::atomic<std::int64_t>::is_always_lock_free, "the page is shared between processes");

inline std::int64_t monotonicNs() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

/// The harness's page, mapped shared; nullptr when `path` cannot be (the component then fails
/// to initialise, which the harness reports).
inline BenchPage* mapPage(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return nullptr;
  void* p = ::mmap(nullptr, sizeof(BenchPage), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ::close(fd);
  return p == MAP_FAILED ? nullptr : static_cast<BenchPage*>(p);
}

}  // namespace keel_bench
