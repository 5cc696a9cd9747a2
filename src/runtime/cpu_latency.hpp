// A wake-up latency request on every CPU (Linux PM QoS, /dev/cpu_dma_latency), held while the
// engine runs (`keel run --cpu-dma-latency US`): an idle CPU may then only enter an idle state
// whose exit latency is at most US µs; at 0 it polls instead of halting. What real-time Linux
// deployments set (cyclictest holds 0 by default): on a VM a halted vCPU costs a VM exit on its
// next wake-up, which about doubles the median time to catch a fault (docs/performance.md,
// "Detection latency"). The price: idle CPUs keep spinning (power; on a VM, host CPU time).
// The request lasts as long as the descriptor stays open: the kernel drops it when the process
// ends, however it ends. Thread-safety: a plain value, used from the thread that owns it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "keel/result.hpp"

namespace keel::runtime {

class CpuLatencyRequest {
 public:
  static constexpr const char* kDevice = "/dev/cpu_dma_latency";

  CpuLatencyRequest() = default;  // holds nothing
  ~CpuLatencyRequest();
  CpuLatencyRequest(CpuLatencyRequest&& other) noexcept;
  CpuLatencyRequest& operator=(CpuLatencyRequest&& other) noexcept;
  CpuLatencyRequest(const CpuLatencyRequest&) = delete;
  CpuLatencyRequest& operator=(const CpuLatencyRequest&) = delete;

  /// Requests at most `us` µs (0..2000000000) until the returned value is destroyed; the
  /// error says why not (no such device, not permitted: needs root).
  static Result<CpuLatencyRequest> hold(std::int32_t us, const std::string& device = kDevice);

  /// The limit in force on the machine now (every process's requests combined), if readable.
  static std::optional<std::int32_t> current(const std::string& device = kDevice);

  bool held() const { return fd_ >= 0; }
  std::int32_t microseconds() const { return us_; }

 private:
  int fd_ = -1;
  std::int32_t us_ = 0;
};

}  // namespace keel::runtime
