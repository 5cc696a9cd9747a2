#include "fault/fault_log.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <system_error>

namespace keel::fault {

FaultLog::FaultLog() : epoch_ns_(steadyNs()) {}

FaultLog::~FaultLog() {
  if (fd_ >= 0) ::close(fd_);
}

Result<void> FaultLog::open(const std::string& path) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return fail(fmt::format("cannot open log '{}': {}", path, std::generic_category().message(errno)));
  fd_ = fd;
  return {};
}

Result<void> FaultLog::join(const std::string& path, std::int64_t epoch_ns) {
  int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd < 0) return fail(fmt::format("cannot open log '{}': {}", path, std::generic_category().message(errno)));
  fd_ = fd;
  epoch_ns_ = epoch_ns;
  return {};
}

void FaultLog::tag(std::string key, nlohmann::json value) { tags_[std::move(key)] = std::move(value); }

std::int64_t FaultLog::now() const { return steadyNs() - epoch_ns_; }

void FaultLog::write(nlohmann::json record) {
  if (fd_ < 0) return;
  if (!record.contains("t_ns")) record["t_ns"] = now();
  for (const auto& [key, value] : tags_.items())
    if (!record.contains(key)) record[key] = value;
  std::string line = record.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  line += '\n';
  std::lock_guard lock(mutex_);
  const char* p = line.data();
  std::size_t left = line.size();
  while (left > 0) {
    ssize_t n = ::write(fd_, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // disk full or closed: the run goes on, the log stops
    p += n;
    left -= static_cast<std::size_t>(n);
  }
}

}  // namespace keel::fault
