#include "runtime/alarm.hpp"

#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <system_error>
#include <utility>

namespace keel::runtime {

Result<Alarm> Alarm::create() {
  const int fd = ::timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
  if (fd < 0) return fail("timerfd_create: " + std::generic_category().message(errno));
  return Alarm(fd);
}

Alarm::~Alarm() {
  if (fd_ >= 0) ::close(fd_);
}

Alarm::Alarm(Alarm&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}

Alarm& Alarm::operator=(Alarm&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

void Alarm::setIn(std::chrono::nanoseconds after) const {
  const std::int64_t ns = after.count() > 0 ? after.count() : 1;  // 0 would disarm it
  itimerspec when{};
  when.it_value.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
  when.it_value.tv_nsec = static_cast<long>(ns % 1'000'000'000);
  ::timerfd_settime(fd_, 0, &when, nullptr);
}

void Alarm::wait() const {
  std::uint64_t expirations = 0;
  while (::read(fd_, &expirations, sizeof expirations) < 0 && errno == EINTR) {}
}

}  // namespace keel::runtime
