#include "runtime/cpu_latency.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

namespace keel::runtime {

CpuLatencyRequest::~CpuLatencyRequest() {
  if (fd_ >= 0) ::close(fd_);
}

CpuLatencyRequest::CpuLatencyRequest(CpuLatencyRequest&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), us_(other.us_) {}

CpuLatencyRequest& CpuLatencyRequest::operator=(CpuLatencyRequest&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    us_ = other.us_;
  }
  return *this;
}

Result<CpuLatencyRequest> CpuLatencyRequest::hold(std::int32_t us, const std::string& device) {
  if (us < 0 || us > 2'000'000'000) return fail(fmt::format("cpu_dma_latency must be 0..2000000000 µs, got {}", us));
  CpuLatencyRequest r;
  r.fd_ = ::open(device.c_str(), O_WRONLY | O_CLOEXEC);
  if (r.fd_ < 0) {
    const int err = errno;
    return fail(fmt::format("cannot hold the CPUs' wake-up latency at {} µs: {}: {}{}", us, device,
                            std::generic_category().message(err),
                            err == EACCES || err == EPERM ? " (needs root)" : ""));
  }
  // The device takes the value as a binary 32-bit integer; the request stands until close.
  if (::write(r.fd_, &us, sizeof us) != static_cast<ssize_t>(sizeof us))
    return fail(fmt::format("cannot hold the CPUs' wake-up latency at {} µs: writing {}: {}", us, device,
                            std::generic_category().message(errno)));
  r.us_ = us;
  return r;
}

std::optional<std::int32_t> CpuLatencyRequest::current(const std::string& device) {
  const int fd = ::open(device.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  std::int32_t v = 0;
  const bool ok = ::read(fd, &v, sizeof v) == static_cast<ssize_t>(sizeof v);
  ::close(fd);
  if (!ok) return std::nullopt;
  return v;
}

}  // namespace keel::runtime
