#include "runtime/checkpoint.hpp"

#include <algorithm>
#include <cstring>
#include <mutex>

namespace keel::runtime {

void takeCheckpoint(detail::ComponentCore& core, std::int64_t now_ns) {
  std::lock_guard lock(core.checkpoint_mutex);
  core.checkpoint.resize(core.critical.size());
  for (std::size_t i = 0; i < core.critical.size(); ++i) {
    const CriticalRegion& r = core.critical[i];
    core.checkpoint[i].resize(r.len);  // allocates only the first time (or when it grew)
    std::memcpy(core.checkpoint[i].data(), r.addr, r.len);
  }
  core.checkpoint_t_ns = now_ns;
  ++core.checkpoint_count;
  core.next_checkpoint_ns = now_ns + core.checkpoint_period_ns;
}

std::int64_t restoreCheckpoint(detail::ComponentCore& core) {
  std::lock_guard lock(core.checkpoint_mutex);
  if (core.checkpoint_t_ns == 0) return 0;
  const std::size_t n = std::min(core.checkpoint.size(), core.critical.size());
  for (std::size_t i = 0; i < n; ++i) {
    const CriticalRegion& r = core.critical[i];
    std::memcpy(r.addr, core.checkpoint[i].data(), std::min(r.len, core.checkpoint[i].size()));
  }
  return n != 0 ? core.checkpoint_t_ns : 0;
}

std::size_t copyCheckpoint(detail::ComponentCore& from, detail::ComponentCore& to) {
  std::lock_guard lock(from.checkpoint_mutex);
  if (from.checkpoint_t_ns == 0) return 0;
  const std::size_t n = std::min(from.checkpoint.size(), to.critical.size());
  for (std::size_t i = 0; i < n; ++i) {
    const CriticalRegion& r = to.critical[i];
    std::memcpy(r.addr, from.checkpoint[i].data(), std::min(r.len, from.checkpoint[i].size()));
  }
  return n;
}

}  // namespace keel::runtime
