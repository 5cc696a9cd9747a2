#include "runtime/ipc/session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <new>

#include "runtime/futex.hpp"

namespace keel::runtime::ipc {
namespace {

constexpr std::uint64_t kMagic = 0x6e6f'6973'7365'736bULL;  // "ksession"
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kLine = 64;

// The supervisor lock and the words every process writes have cache lines of their own.
struct SessionHeader {  // NOLINT(clang-analyzer-optin.performance.Padding): see above
  std::uint64_t magic = 0;
  std::uint32_t version = 0;
  std::uint32_t reserved = 0;
  std::uint64_t processes = 0;
  std::uint64_t rings = 0;
  std::uint64_t checkpoints = 0;
  std::uint64_t plan_hash = 0;
  alignas(64) RobustMutex supervisor;
  alignas(64) std::atomic<std::uint64_t> fault_ids{1};
  std::atomic<std::int64_t> log_epoch{0};
};

struct alignas(64) RingWord {
  std::atomic<std::uint32_t> ready{0};
  std::atomic<std::uint64_t> consumed{0};
};

static_assert(std::atomic<std::uint64_t>::is_always_lock_free && std::atomic<std::int64_t>::is_always_lock_free);

constexpr std::size_t roundUp(std::size_t n) { return (n + kLine - 1) / kLine * kLine; }

struct Layout {
  std::size_t processes, rings, checkpoints, log, total;
};

Layout layoutOf(const SessionShape& s) {
  Layout l{};
  l.processes = roundUp(sizeof(SessionHeader));
  l.rings = l.processes + roundUp(sizeof(ProcessBlock)) * s.processes;
  l.checkpoints = l.rings + sizeof(RingWord) * s.rings;
  l.log = l.checkpoints + roundUp(sizeof(CheckpointArea)) * s.checkpoints;
  l.total = l.log + roundUp(sizeof(LogArena)) + roundUp(sizeof(LogStage)) * (1 + s.processes * kHostSlots);
  return l;
}

SessionHeader& headerOf(const SharedMemory& m) { return *std::launder(reinterpret_cast<SessionHeader*>(m.data())); }

}  // namespace

std::string_view toString(HostState s) {
  switch (s) {
    case HostState::Free: return "free";
    case HostState::Starting: return "starting";
    case HostState::Loading: return "loading";
    case HostState::Standby: return "standby";
    case HostState::Active: return "active";
    case HostState::Exited: return "exited";
    case HostState::Failed: return "failed";
  }
  return "?";
}

Session::Session(SharedMemory memory, const SessionShape& shape) : memory_(std::move(memory)), shape_(shape) {}

Result<Session> Session::create(const SessionShape& shape) {
  const Layout l = layoutOf(shape);
  auto memory = SharedMemory::create("keel-session", l.total);
  if (!memory) return memory.error();
  std::byte* base = memory->data();
  auto* h = new (base) SessionHeader();
  h->magic = kMagic;
  h->version = kVersion;
  h->processes = shape.processes;
  h->rings = shape.rings;
  h->checkpoints = shape.checkpoints;
  h->plan_hash = shape.plan_hash;
  if (auto r = h->supervisor.init(); !r) return r.error();
  for (std::size_t i = 0; i < shape.processes; ++i) {
    auto* b = new (base + l.processes + roundUp(sizeof(ProcessBlock)) * i) ProcessBlock();
    if (auto r = b->role.init(); !r) return r.error();
    for (HostSlot& slot : b->slots)
      if (auto r = slot.life.init(); !r) return r.error();
  }
  for (std::size_t i = 0; i < shape.rings; ++i) new (base + l.rings + sizeof(RingWord) * i) RingWord();
  for (std::size_t i = 0; i < shape.checkpoints; ++i)
    new (base + l.checkpoints + roundUp(sizeof(CheckpointArea)) * i) CheckpointArea();
  auto* arena = new (base + l.log) LogArena();
  if (auto r = arena->lock.init(); !r) return r.error();
  arena->stage_count = 1 + shape.processes * kHostSlots;
  for (std::size_t i = 0; i < arena->stage_count; ++i)
    new (base + l.log + roundUp(sizeof(LogArena)) + roundUp(sizeof(LogStage)) * i) LogStage();
  return Session(std::move(*memory), shape);
}

Result<Session> Session::adopt(int fd, const SessionShape& shape) {
  auto memory = SharedMemory::adopt(fd, "keel-session");
  if (!memory) return memory.error();
  if (memory->size() < sizeof(SessionHeader)) return fail("the session region is too small");
  const SessionHeader& h = headerOf(*memory);
  if (h.magic != kMagic || h.version != kVersion) return fail("the inherited region is not a keel session");
  if (h.processes != shape.processes || h.rings != shape.rings || h.checkpoints != shape.checkpoints ||
      h.plan_hash != shape.plan_hash)
    return fail(
        "the session was made for another plan (the profiles changed since keel run read them, or another "
        "--set was given)");
  if (memory->size() < layoutOf(shape).total) return fail("the session region is too small for its plan");
  return Session(std::move(*memory), shape);
}

RobustMutex& Session::supervisor() { return headerOf(memory_).supervisor; }
std::atomic<std::uint64_t>& Session::faultIds() { return headerOf(memory_).fault_ids; }
std::atomic<std::int64_t>& Session::logEpoch() { return headerOf(memory_).log_epoch; }

ProcessBlock& Session::process(std::size_t i) {
  if (i >= shape_.processes) std::abort();  // an index from the plan: a bug, not input
  return *std::launder(
      reinterpret_cast<ProcessBlock*>(memory_.data() + layoutOf(shape_).processes + roundUp(sizeof(ProcessBlock)) * i));
}

std::atomic<std::uint32_t>& Session::ringReady(std::size_t i) {
  if (i >= shape_.rings) std::abort();
  return std::launder(reinterpret_cast<RingWord*>(memory_.data() + layoutOf(shape_).rings))[i].ready;
}

void Session::abandonRings() {
  for (std::size_t i = 0; i < shape_.rings; ++i) {
    std::uint32_t pending = kRingPending;
    if (ringReady(i).compare_exchange_strong(pending, kRingAbandoned, std::memory_order_acq_rel))
      runtime::futexWakeAll(ringReady(i), runtime::FutexScope::Shared);
  }
}

LogArena& Session::log() { return *std::launder(reinterpret_cast<LogArena*>(memory_.data() + layoutOf(shape_).log)); }

LogStage& logStage(LogArena& arena, std::size_t i) {
  if (i >= arena.stage_count) std::abort();  // an index from the plan: a bug, not input
  return *std::launder(reinterpret_cast<LogStage*>(reinterpret_cast<std::byte*>(&arena) + roundUp(sizeof(LogArena)) +
                                                   roundUp(sizeof(LogStage)) * i));
}

std::size_t logParticipant(std::optional<std::size_t> process, std::size_t slot) {
  return process ? 1 + *process * kHostSlots + slot : 0;
}

std::atomic<std::uint64_t>& Session::ringConsumed(std::size_t i) {
  if (i >= shape_.rings) std::abort();
  return std::launder(reinterpret_cast<RingWord*>(memory_.data() + layoutOf(shape_).rings))[i].consumed;
}

CheckpointArea& Session::checkpoint(std::size_t i) {
  if (i >= shape_.checkpoints) std::abort();
  return *std::launder(reinterpret_cast<CheckpointArea*>(memory_.data() + layoutOf(shape_).checkpoints +
                                                         roundUp(sizeof(CheckpointArea)) * i));
}

void publishState(ProcessBlock& block, HostSlot& slot, HostState state) {
  slot.state.store(static_cast<std::uint32_t>(state), std::memory_order_release);
  block.changes.fetch_add(1, std::memory_order_acq_rel);
  futexWakeAll(block.changes, FutexScope::Shared);
}

void setMessage(HostSlot& slot, std::string_view text) {
  const std::size_t n = std::min(text.size(), sizeof slot.message);
  std::memcpy(slot.message, text.data(), n);
  slot.message_len.store(static_cast<std::uint32_t>(n), std::memory_order_release);
}

std::string messageOf(const HostSlot& slot) {
  const std::size_t n = std::min<std::size_t>(slot.message_len.load(std::memory_order_acquire), sizeof slot.message);
  return {slot.message, n};
}

void publishCommand(ProcessBlock& block, Command command) {
  block.command.store(static_cast<std::uint32_t>(command), std::memory_order_release);
  futexWakeAll(block.command, FutexScope::Shared);
  block.changes.fetch_add(1, std::memory_order_acq_rel);
  futexWakeAll(block.changes, FutexScope::Shared);
}

bool publishCheckpoint(CheckpointArea& area, const std::vector<std::vector<std::byte>>& copies, std::int64_t t_ns) {
  std::size_t need = sizeof(std::uint64_t) * (1 + copies.size());
  for (const auto& c : copies) need += c.size();
  if (need > kCheckpointBytes) return false;
  const std::uint64_t seq = area.seq.load(std::memory_order_relaxed);
  const std::size_t b = (seq + 1) & 1;  // the buffer not published now
  std::byte* out = area.data[b];
  const std::uint64_t n = copies.size();
  std::memcpy(out, &n, sizeof n);
  out += sizeof n;
  for (const auto& c : copies) {
    const std::uint64_t len = c.size();
    std::memcpy(out, &len, sizeof len);
    out += sizeof len;
  }
  for (const auto& c : copies) {
    if (!c.empty()) std::memcpy(out, c.data(), c.size());
    out += c.size();
  }
  area.bytes[b] = need;
  area.t_ns[b] = t_ns;
  area.seq.store(seq + 1, std::memory_order_release);
  return true;
}

void prefaultCheckpoint(const CheckpointArea& area, const std::vector<std::vector<std::byte>>& copies) {
  std::size_t need = sizeof(std::uint64_t) * (1 + copies.size());
  for (const auto& c : copies) need += c.size();
  need = std::min(need, kCheckpointBytes);
  constexpr std::size_t kPage = 4096;
  for (const auto& buffer : area.data)
    for (std::size_t off = 0; off < need; off += kPage) {
      const auto* byte = reinterpret_cast<const volatile std::byte*>(buffer + off);
      (void)*byte;
    }
}

std::optional<std::int64_t> readCheckpoint(const CheckpointArea& area, const std::vector<std::size_t>& lengths,
                                           std::vector<std::vector<std::byte>>& copies) {
  const std::uint64_t seq = area.seq.load(std::memory_order_acquire);
  if (seq == 0) return std::nullopt;
  const std::size_t b = seq & 1 ? 1 : 0;
  const std::byte* in = area.data[b];
  const std::uint64_t bytes = std::min<std::uint64_t>(area.bytes[b], kCheckpointBytes);
  std::uint64_t n = 0;
  if (bytes < sizeof n) return std::nullopt;
  std::memcpy(&n, in, sizeof n);
  if (n != lengths.size() || bytes < sizeof(std::uint64_t) * (1 + n)) return std::nullopt;
  std::uint64_t total = sizeof(std::uint64_t) * (1 + n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t len = 0;
    std::memcpy(&len, in + sizeof(std::uint64_t) * (1 + i), sizeof len);
    if (len != lengths[i]) return std::nullopt;
    total += len;
  }
  if (total != bytes) return std::nullopt;
  const std::byte* from = in + sizeof(std::uint64_t) * (1 + n);
  copies.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    copies[i].assign(from, from + lengths[i]);
    from += lengths[i];
  }
  return area.t_ns[b];
}

}  // namespace keel::runtime::ipc
