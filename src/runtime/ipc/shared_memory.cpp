#include "runtime/ipc/shared_memory.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>
#include <utility>

namespace keel::runtime::ipc {
namespace {

std::string errnoText(int err) { return std::generic_category().message(err); }

// Maps `size` bytes of `fd` read-write and shared, faulting every page in now (MAP_POPULATE)
// so that the first push or pop into a fresh region takes no page fault.
std::byte* mapShared(int fd, std::size_t size) {
  void* p = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_POPULATE, fd, 0);
  return p == MAP_FAILED ? nullptr : static_cast<std::byte*>(p);
}

}  // namespace

Result<SharedMemory> SharedMemory::create(const std::string& name, std::size_t size) {
  const auto why = [&](const char* step, int err) {
    return fail(fmt::format("cannot create shared memory '{}' of {} bytes: {}: {}", name, size, step, errnoText(err)));
  };
  if (size == 0) return fail(fmt::format("cannot create shared memory '{}': its size must be above 0", name));
  SharedMemory m;
  m.name_ = name;
  m.fd_ = ::memfd_create(name.c_str(), MFD_CLOEXEC | MFD_ALLOW_SEALING);
  if (m.fd_ < 0) return why("memfd_create", errno);
  if (::ftruncate(m.fd_, static_cast<off_t>(size)) != 0) return why("ftruncate", errno);
  if (::fcntl(m.fd_, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL) != 0)
    return why("sealing its size", errno);
  m.data_ = mapShared(m.fd_, size);
  if (!m.data_) return why("mmap", errno);
  m.size_ = size;
  return m;
}

Result<SharedMemory> SharedMemory::adopt(int fd, const std::string& name) {
  SharedMemory m = adoptUnmapped(fd, name);  // owns fd from here: closed with m on an error
  if (auto r = m.map(); !r) return r.error();
  return m;
}

Result<SharedMemory> SharedMemory::createUnsized(const std::string& name) {
  SharedMemory m;
  m.name_ = name;
  m.fd_ = ::memfd_create(name.c_str(), MFD_CLOEXEC | MFD_ALLOW_SEALING);
  if (m.fd_ < 0) return fail(fmt::format("cannot create shared memory '{}': memfd_create: {}", name, errnoText(errno)));
  return m;
}

SharedMemory SharedMemory::adoptUnmapped(int fd, const std::string& name) {
  SharedMemory m;
  m.fd_ = fd;
  m.name_ = name;
  return m;
}

Result<void> SharedMemory::sizeTo(std::size_t size) {
  const auto why = [&](const char* step, int err) {
    return fail(fmt::format("cannot size shared memory '{}' to {} bytes: {}: {}", name_, size, step, errnoText(err)));
  };
  if (size == 0 || data_) return fail(fmt::format("cannot size shared memory '{}': mapped already, or size 0", name_));
  struct stat st {};
  if (::fstat(fd_, &st) != 0) return why("fstat", errno);
  if (st.st_size != 0) return fail(fmt::format("cannot size shared memory '{}': it has a size already", name_));
  if (::ftruncate(fd_, static_cast<off_t>(size)) != 0) return why("ftruncate", errno);
  if (::fcntl(fd_, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL) != 0) return why("sealing its size", errno);
  data_ = mapShared(fd_, size);
  if (!data_) return why("mmap", errno);
  size_ = size;
  return {};
}

Result<void> SharedMemory::map() {
  if (data_) return {};
  struct stat st {};
  if (::fstat(fd_, &st) != 0)
    return fail(fmt::format("cannot map shared memory '{}' (fd {}): fstat: {}", name_, fd_, errnoText(errno)));
  if (st.st_size <= 0) return fail(fmt::format("cannot map shared memory '{}' (fd {}): it is empty", name_, fd_));
  const auto size = static_cast<std::size_t>(st.st_size);
  data_ = mapShared(fd_, size);
  if (!data_) return fail(fmt::format("cannot map shared memory '{}' (fd {}): mmap: {}", name_, fd_, errnoText(errno)));
  size_ = size;
  return {};
}

SharedMemory::~SharedMemory() { release(); }

SharedMemory::SharedMemory(SharedMemory&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), data_(std::exchange(other.data_, nullptr)),
      size_(std::exchange(other.size_, 0)), name_(std::move(other.name_)) {}

SharedMemory& SharedMemory::operator=(SharedMemory&& other) noexcept {
  if (this != &other) {
    release();
    fd_ = std::exchange(other.fd_, -1);
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
    name_ = std::move(other.name_);
  }
  return *this;
}

void SharedMemory::release() noexcept {
  if (data_) ::munmap(data_, size_);
  if (fd_ >= 0) ::close(fd_);
  data_ = nullptr;
  size_ = 0;
  fd_ = -1;
}

}  // namespace keel::runtime::ipc
