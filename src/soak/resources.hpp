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
  std::size_t fds = 0;
};

/// This process's resident memory and open descriptors now.
Usage usageNow();

/// The processes whose parent is this process, as "pid (name)", zombies (ended, never waited
/// for) included.
std::vector<std::string> childrenNow();

}  // namespace keel::soak
