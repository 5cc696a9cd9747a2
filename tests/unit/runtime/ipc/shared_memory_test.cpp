// Shared memory (runtime/ipc/shared_memory.hpp): one region seen through mappings of two
// processes, sealed against resizing, moved without being unmapped, and clear errors.
#include "runtime/ipc/shared_memory.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "ipc_test_support.hpp"

namespace keel::runtime::ipc {
namespace {

using test::Child;
using test::must;

TEST(SharedMemory, WhatAnotherProcessWritesThroughItsOwnMappingIsSeenHere) {
  auto region = must(SharedMemory::create("test region", 10000));
  ASSERT_EQ(region.size(), 10000u);
  ASSERT_EQ(region.data()[9999], std::byte{0}) << "a new region is zero-filled";

  const int fd = region.fd();
  Child writer = Child::run([fd] {
    auto own = SharedMemory::adopt(::dup(fd), "test region");  // a mapping of its own
    if (!own || own->size() != 10000) return 2;
    std::memcpy(own->data() + 5000, "across", 7);
    return 0;
  });
  EXPECT_TRUE(test::exitedWith(writer.wait(), 0));
  EXPECT_STREQ(reinterpret_cast<const char*>(region.data() + 5000), "across");

  auto second = must(SharedMemory::adopt(::dup(fd), "second view"));
  EXPECT_NE(second.data(), region.data()) << "a second mapping, at its own address";
  second.data()[1] = std::byte{7};
  EXPECT_EQ(region.data()[1], std::byte{7});
  EXPECT_EQ(second.name(), "second view");
}

TEST(SharedMemory, ItsSizeIsSealedSoNoProcessSharingItCanShrinkIt) {
  auto region = must(SharedMemory::create("sealed", 4096));
  EXPECT_NE(::ftruncate(region.fd(), 0), 0);
  EXPECT_EQ(errno, EPERM);
  EXPECT_NE(::ftruncate(region.fd(), 8192), 0);
  EXPECT_EQ(errno, EPERM);
  EXPECT_EQ(::fcntl(region.fd(), F_GETFD) & FD_CLOEXEC, FD_CLOEXEC) << "passed on by dup2 only, never leaked by exec";
}

TEST(SharedMemory, AMoveHandsTheMappingOnAndDestroyingTheOwnerReleasesIt) {
  auto region = must(SharedMemory::create("moved", 4096));
  std::byte* data = region.data();
  const int fd = region.fd();
  data[0] = std::byte{1};

  SharedMemory owner = std::move(region);
  // NOLINTNEXTLINE(bugprone-use-after-move,clang-analyzer-cplusplus.Move): the moved-from state is the point
  EXPECT_FALSE(region.mapped());
  EXPECT_EQ(owner.data(), data);
  EXPECT_EQ(owner.data()[0], std::byte{1});

  owner = must(SharedMemory::create("other", 4096));
  EXPECT_EQ(::fcntl(fd, F_GETFD), -1) << "the first region's fd was closed when assigned over";
  EXPECT_EQ(errno, EBADF);
}

TEST(SharedMemory, ErrorsNameTheRegionTheStepAndTheSystemsReason) {
  auto empty = SharedMemory::create("ring cam→det", 0);
  ASSERT_FALSE(empty);
  EXPECT_EQ(empty.error().message, "cannot create shared memory 'ring cam→det': its size must be above 0");

  auto bad_fd = SharedMemory::adopt(-1, "ring cam→det");
  ASSERT_FALSE(bad_fd);
  EXPECT_EQ(bad_fd.error().message, "cannot map shared memory 'ring cam→det' (fd -1): fstat: Bad file descriptor");

  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  ::close(pipe_fds[1]);
  auto not_memory = SharedMemory::adopt(pipe_fds[0], "a pipe");  // closed by adopt, even on failure
  ASSERT_FALSE(not_memory);
  EXPECT_NE(not_memory.error().message.find("'a pipe'"), std::string::npos) << not_memory.error().message;
  EXPECT_EQ(::fcntl(pipe_fds[0], F_GETFD), -1) << "adopt owns the fd on failure too";
}

}  // namespace
}  // namespace keel::runtime::ipc
