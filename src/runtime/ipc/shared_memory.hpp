// SharedMemory: one region of memory shared between processes, backed by a memfd (an anonymous
// file: nothing in /dev/shm to clean up after a crash; it lives while a descriptor or a mapping
// of it does). The supervisor creates a region (a ring, a control block) and hands its descriptor
// to the component process it starts, which adopts it; each side maps it MAP_SHARED at its own
// address, so what lives inside holds offsets or indices, never pointers.
// A created region is sealed against resizing, so no process sharing it can shrink it under the
// others (accessing a truncated mapping raises SIGBUS). The descriptor is close-on-exec: a
// spawner passes it on by dup2 into the child (posix_spawn_file_actions_adddup2 clears the flag).
// In /proc/<pid>/maps a region shows as "/memfd:<name> (deleted)".
// Thread-safety: a move-only handle; its memory is shared, and what lives there says how to use it.
#pragma once

#include <cstddef>
#include <string>

#include "keel/result.hpp"

namespace keel::runtime::ipc {

class SharedMemory {
 public:
  /// A new zero-filled region of `size` bytes (> 0); `name` is for diagnostics only.
  static Result<SharedMemory> create(const std::string& name, std::size_t size);
  /// Maps the region behind `fd` (inherited from the process that created it), whole. Takes
  /// ownership of `fd` in every case: it is closed with the region, or at once on an error.
  static Result<SharedMemory> adopt(int fd, const std::string& name = "inherited");
  /// A region with no size yet, mapped nowhere: the side that learns the size gives it one
  /// with sizeTo() (a port's ring: keel run creates it, the writer's process sizes it).
  static Result<SharedMemory> createUnsized(const std::string& name);
  /// Takes ownership of `fd` without mapping it (an inherited region that may not be sized yet).
  static SharedMemory adoptUnmapped(int fd, const std::string& name = "inherited");
  /// Sizes an unsized region (sealing it) and maps it; an error when it has a size already.
  Result<void> sizeTo(std::size_t size);
  /// Maps an adoptUnmapped() region, whole; an error while it has no size.
  Result<void> map();

  SharedMemory() = default;  // maps nothing
  ~SharedMemory();
  SharedMemory(SharedMemory&& other) noexcept;
  SharedMemory& operator=(SharedMemory&& other) noexcept;
  SharedMemory(const SharedMemory&) = delete;
  SharedMemory& operator=(const SharedMemory&) = delete;

  bool mapped() const { return data_ != nullptr; }
  /// The start of the mapping (page-aligned), or null when nothing is mapped.
  std::byte* data() const { return data_; }
  std::size_t size() const { return size_; }
  /// The memfd, to hand to another process; owned by this object (dup it to keep it longer).
  int fd() const { return fd_; }
  const std::string& name() const { return name_; }

 private:
  void release() noexcept;

  int fd_ = -1;
  std::byte* data_ = nullptr;
  std::size_t size_ = 0;
  std::string name_;
};

}  // namespace keel::runtime::ipc
