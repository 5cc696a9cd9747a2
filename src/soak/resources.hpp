// What the soak watches of its own process between rounds (docs/soak.md): resident memory,
// open file descriptors, and the processes it started that are still running.
// Thread-safety: functions of /proc.
#pragma once

#include <sys/types.h>
#include <cstdint>
#include <string>
#include <vector>

namespace keel::soak {

struct Usage {
  std::uint64_t rss_bytes = 0;
  std::uint64_t heap_bytes = 0;  // allocated and not freed (glibc's count, or ASan's allocator's)
  std::size_t fds = 0;
};

/// Whether this build runs under AddressSanitizer. Its resident memory is then mostly ASan's
/// shadow and bookkeeping (a record of every thread that ever ran, of every allocation's stack),
/// which grows on its own run after run: the heap in use is what says whether keel leaks.
#if defined(__SANITIZE_ADDRESS__)  // GCC
#define KEEL_SOAK_UNDER_ASAN 1
#elif defined(__has_feature)  // clang
#if __has_feature(address_sanitizer)
#define KEEL_SOAK_UNDER_ASAN 1
#endif
#endif
#if defined(KEEL_SOAK_UNDER_ASAN)
inline constexpr bool kUnderAsan = true;
#else
inline constexpr bool kUnderAsan = false;
#endif

/// This process's resident memory, heap in use and open descriptors now. With `trim`, free heap
/// memory is given back to the system first (malloc_trim: it locks the allocator for a moment),
/// so that resident memory is what is held, not what the allocator keeps from the busiest moment.
Usage usageNow(bool trim = false);

/// The processes whose parent is this process, as "pid (name)", zombies (ended, never waited
/// for) included.
std::vector<std::string> childrenNow();

}  // namespace keel::soak
