#include "runtime/checkpoint.hpp"

#include <algorithm>
#include <cstring>
#include <mutex>
#include <vector>

#include "runtime/ipc/session.hpp"

namespace keel::runtime {

void takeCheckpoint(detail::ComponentCore& core, std::int64_t now_ns) {
  std::lock_guard lock(core.checkpoints.mutex);
  core.checkpoints.copies.resize(core.critical.size());
  for (std::size_t i = 0; i < core.critical.size(); ++i) {
    const CriticalRegion& r = core.critical[i];
    core.checkpoints.copies[i].resize(r.len);  // allocates only the first time (or when it grew)
    std::memcpy(core.checkpoints.copies[i].data(), r.addr, r.len);
  }
  core.checkpoints.t_ns = now_ns;
  ++core.checkpoints.count;
  core.checkpoints.next_ns = now_ns + core.checkpoints.period_ns;
  if (core.checkpoints.shared) ipc::publishCheckpoint(*core.checkpoints.shared, core.checkpoints.copies, now_ns);
}

void reserveCheckpoint(detail::ComponentCore& core) {
  std::lock_guard lock(core.checkpoints.mutex);
  core.checkpoints.copies.resize(core.critical.size());
  for (std::size_t i = 0; i < core.critical.size(); ++i) core.checkpoints.copies[i].resize(core.critical[i].len);
  if (core.checkpoints.shared) ipc::prefaultCheckpoint(*core.checkpoints.shared, core.checkpoints.copies);
}

std::int64_t restoreSharedCheckpoint(detail::ComponentCore& core) {
  if (!core.checkpoints.shared) return 0;
  std::vector<std::size_t> lengths;
  for (const CriticalRegion& r : core.critical) lengths.push_back(r.len);
  {
    std::lock_guard lock(core.checkpoints.mutex);
    auto t = ipc::readCheckpoint(*core.checkpoints.shared, lengths, core.checkpoints.copies);
    if (!t) return 0;
    core.checkpoints.t_ns = *t;
  }
  return restoreCheckpoint(core);
}

std::int64_t restoreCheckpoint(detail::ComponentCore& core) {
  std::lock_guard lock(core.checkpoints.mutex);
  if (core.checkpoints.t_ns == 0) return 0;
  const std::size_t n = std::min(core.checkpoints.copies.size(), core.critical.size());
  for (std::size_t i = 0; i < n; ++i) {
    const CriticalRegion& r = core.critical[i];
    std::memcpy(r.addr, core.checkpoints.copies[i].data(), std::min(r.len, core.checkpoints.copies[i].size()));
  }
  return n != 0 ? core.checkpoints.t_ns : 0;
}

std::size_t copyCheckpoint(detail::ComponentCore& from, detail::ComponentCore& to) {
  std::lock_guard lock(from.checkpoints.mutex);
  if (from.checkpoints.t_ns == 0) return 0;
  const std::size_t n = std::min(from.checkpoints.copies.size(), to.critical.size());
  for (std::size_t i = 0; i < n; ++i) {
    const CriticalRegion& r = to.critical[i];
    std::memcpy(r.addr, from.checkpoints.copies[i].data(), std::min(r.len, from.checkpoints.copies[i].size()));
  }
  return n;
}

}  // namespace keel::runtime
