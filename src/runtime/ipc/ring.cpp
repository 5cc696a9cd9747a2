#include "runtime/ipc/ring.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <new>

#include "runtime/futex.hpp"
#include "runtime/ipc/robust_mutex.hpp"

// ThreadSanitizer does not model fences, and GCC says so for each one (-Wtsan). Every word the
// ring shares is an atomic, so TSan still sees every access and reports no race the fences
// would have prevented; what it cannot check is the fences' ordering, which the ring's
// cross-process tests check under the other builds.
#if defined(__SANITIZE_THREAD__)
#pragma GCC diagnostic ignored "-Wtsan"
#endif

namespace keel::runtime::ipc {

namespace detail {

// The ring's header at the start of its region. Everything another process may change is an
// atomic; the geometry is written once by create(), before the region is shared. The padding is
// the point: the writer's lock, the words it writes on every push and the readers' words each
// have a cache line of their own.
struct RingHeader {  // NOLINT(clang-analyzer-optin.performance.Padding): see above
  std::uint64_t magic = 0;
  std::uint32_t version = 0;
  std::uint32_t sample_size = 0;
  std::uint64_t slots = 0;
  alignas(64) RobustMutex writer;                  // held around each push and takeOver
  alignas(64) std::atomic<std::uint64_t> head{0};  // samples committed; written under `writer`
  std::atomic<std::uint32_t> epoch{0};             // the current writer's; written under `writer`
  alignas(64) std::atomic<std::uint32_t> wake{0};  // futex word: bumped to wake sleeping readers
  std::atomic<std::uint32_t> sleepers{0};          // readers that announced they sleep on `wake`
};

}  // namespace detail

namespace {

using detail::RingHeader;

constexpr std::uint64_t kMagic = 0x676e'6972'6c65'656bULL;  // "keelring"
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kMaxSize = std::size_t{1} << 24;  // of a sample, and of the slot count
constexpr std::size_t kLine = 64;                       // a slot starts on a cache line of its own

// A slot: this header, then the sample in whole 64-bit words.
struct SlotHeader {
  std::atomic<std::uint64_t> seq{0};    // 2i+1 while sample i is written, 2i+2 once committed
  std::atomic<std::uint32_t> epoch{0};  // of the writer of the sample
  std::uint32_t reserved = 0;
};

static_assert(std::atomic<std::uint64_t>::is_always_lock_free && std::atomic<std::uint32_t>::is_always_lock_free,
              "atomics shared between processes must be lock-free (address-free)");
static_assert(std::atomic_ref<std::uint64_t>::is_always_lock_free);
static_assert(sizeof(SlotHeader) % 8 == 0);

constexpr std::size_t roundUp(std::size_t n, std::size_t to) { return (n + to - 1) / to * to; }
constexpr std::size_t kHeaderBytes = roundUp(sizeof(RingHeader), kLine);
constexpr std::size_t strideFor(std::size_t sample_size) {
  return roundUp(sizeof(SlotHeader) + roundUp(sample_size, 8), kLine);
}

SlotHeader& slotAt(std::byte* slots, std::size_t stride, std::uint64_t mask, std::uint64_t index) {
  return *std::launder(reinterpret_cast<SlotHeader*>(slots + (index & mask) * stride));
}
std::uint64_t* wordsOf(SlotHeader& slot) { return reinterpret_cast<std::uint64_t*>(&slot + 1); }

// The sample moves as relaxed atomic 64-bit words: a reader racing the writer reads words of
// either sample (and then throws the copy away), which the memory model allows, unlike memcpy.
void storeWords(std::uint64_t* to, const void* from, std::size_t bytes) {
  const auto* src = static_cast<const std::byte*>(from);
  for (std::size_t off = 0; off < bytes; off += 8) {
    std::uint64_t w = 0;
    std::memcpy(&w, src + off, std::min<std::size_t>(8, bytes - off));
    std::atomic_ref<std::uint64_t>(to[off / 8]).store(w, std::memory_order_relaxed);
  }
}
void loadWords(void* to, std::uint64_t* from, std::size_t bytes) {
  auto* dst = static_cast<std::byte*>(to);
  for (std::size_t off = 0; off < bytes; off += 8) {
    const std::uint64_t w = std::atomic_ref<std::uint64_t>(from[off / 8]).load(std::memory_order_relaxed);
    std::memcpy(dst + off, &w, std::min<std::size_t>(8, bytes - off));
  }
}

Result<void> checkSizes(const std::string& name, std::size_t sample_size, std::size_t slots) {
  if (sample_size == 0 || sample_size > kMaxSize)
    return fail(fmt::format("ring '{}': a sample of {} bytes; it must be 1..{}", name, sample_size, kMaxSize));
  if (slots == 0 || slots > kMaxSize || !std::has_single_bit(slots))
    return fail(fmt::format("ring '{}': {} slots; the count must be a power of two, 1..{}", name, slots, kMaxSize));
  return {};
}

/// Whether a region of `bytes` holds the ring's header and `slots` slots of `sample_size`.
Result<void> checkRegion(const std::string& name, std::size_t bytes, std::size_t sample_size, std::size_t slots) {
  const std::size_t needed = RingBuffer::bytesFor(sample_size, slots);
  if (bytes < needed)
    return fail(fmt::format("ring '{}': {} slots of {} bytes need {} bytes, the region has {}", name, slots,
                            sample_size, needed, bytes));
  return {};
}

}  // namespace

std::size_t RingBuffer::bytesFor(std::size_t sample_size, std::size_t slots) {
  return kHeaderBytes + slots * strideFor(sample_size);
}

Result<RingBuffer> RingBuffer::create(const std::string& name, std::size_t sample_size, std::size_t slots) {
  if (auto sizes = checkSizes(name, sample_size, slots); !sizes) return sizes.error();
  auto region = SharedMemory::create(name, bytesFor(sample_size, slots));
  if (!region) return region.error();
  return create(std::move(*region), sample_size, slots);
}

Result<RingBuffer> RingBuffer::create(SharedMemory region, std::size_t sample_size, std::size_t slots) {
  if (auto sizes = checkSizes(region.name(), sample_size, slots); !sizes) return sizes.error();
  if (auto fits = checkRegion(region.name(), region.size(), sample_size, slots); !fits) return fits.error();
  auto* header = new (region.data()) RingHeader();
  header->magic = kMagic;
  header->version = kVersion;
  header->sample_size = static_cast<std::uint32_t>(sample_size);
  header->slots = slots;
  if (auto init = header->writer.init(); !init)
    return fail(fmt::format("ring '{}': writer lock: {}", region.name(), init.error().message));
  std::byte* first = region.data() + kHeaderBytes;
  for (std::size_t i = 0; i < slots; ++i) new (first + i * strideFor(sample_size)) SlotHeader();
  return RingBuffer(std::move(region), sample_size, slots);
}

Result<RingBuffer> RingBuffer::attach(SharedMemory region, std::size_t sample_size) {
  const std::string& name = region.name();
  if (region.size() < kHeaderBytes) return fail(fmt::format("'{}' is not a keel ring: {} bytes", name, region.size()));
  const auto* header = std::launder(reinterpret_cast<const RingHeader*>(region.data()));
  // Read once: what is checked here is what this process keeps using.
  const std::uint64_t magic = header->magic, slots = header->slots;
  const std::uint32_t version = header->version, size = header->sample_size;
  if (magic != kMagic || version != kVersion)
    return fail(
        fmt::format("'{}' is not a keel ring of version {} (magic {:#x}, version {})", name, kVersion, magic, version));
  if (size != sample_size)
    return fail(fmt::format("ring '{}' carries samples of {} bytes, this side expects {}", name, size, sample_size));
  if (auto sizes = checkSizes(name, size, slots); !sizes) return sizes.error();
  if (auto fits = checkRegion(name, region.size(), size, slots); !fits) return fits.error();
  return RingBuffer(std::move(region), sample_size, slots);
}

RingBuffer::RingBuffer(SharedMemory region, std::size_t sample_size, std::size_t slots)
    : memory_(std::move(region)), header_(std::launder(reinterpret_cast<RingHeader*>(memory_.data()))),
      slots_(memory_.data() + kHeaderBytes), mask_(slots - 1), stride_(strideFor(sample_size)),
      sample_size_(sample_size) {}

Result<bool> RingBuffer::lockWriter() {
  auto locked = header_->writer.lock();
  if (!locked) return fail(fmt::format("ring '{}': writer lock: {}", memory_.name(), locked.error().message));
  if (*locked != LockStatus::OwnerDied) return false;
  // The last writer died holding the lock. If it committed sample i but died before publishing
  // the head, keep the sample; a slot it left half-written (odd) is simply written again.
  const std::uint64_t i = header_->head.load(std::memory_order_relaxed);
  if (slotAt(slots_, stride_, mask_, i).seq.load(std::memory_order_acquire) == 2 * i + 2)
    header_->head.store(i + 1, std::memory_order_release);
  return true;
}

Result<void> RingBuffer::unlockWriter() {
  if (auto unlocked = header_->writer.unlock(); !unlocked)
    return fail(fmt::format("ring '{}': writer lock: {}", memory_.name(), unlocked.error().message));
  return {};
}

Result<TakeOver> RingBuffer::takeOver() {
  auto died = lockWriter();
  if (!died) return died.error();
  std::uint32_t epoch = header_->epoch.load(std::memory_order_relaxed) + 1;
  if (epoch == 0) epoch = 1;  // wrapped: 0 stays "no writer"
  header_->epoch.store(epoch, std::memory_order_release);
  if (auto unlocked = unlockWriter(); !unlocked) return unlocked.error();
  return TakeOver{epoch, *died};
}

Result<PushStatus> RingBuffer::push(std::uint32_t epoch, const void* sample) {
  if (auto died = lockWriter(); !died) return died.error();
  if (epoch == 0 || header_->epoch.load(std::memory_order_relaxed) != epoch) {
    if (auto unlocked = unlockWriter(); !unlocked) return unlocked.error();
    return PushStatus::Fenced;
  }
  const std::uint64_t i = header_->head.load(std::memory_order_relaxed);
  SlotHeader& slot = slotAt(slots_, stride_, mask_, i);
  slot.seq.store(2 * i + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);  // odd before any word of the sample
  slot.epoch.store(epoch, std::memory_order_relaxed);
  storeWords(wordsOf(slot), sample, sample_size_);
  slot.seq.store(2 * i + 2, std::memory_order_release);
  header_->head.store(i + 1, std::memory_order_release);
  if (auto unlocked = unlockWriter(); !unlocked) return unlocked.error();
  // Wake sleepers, if any announced it: the fence pairs with the reader's between its announce
  // and its last look at the head (one of the two sees the other's write).
  std::atomic_thread_fence(std::memory_order_seq_cst);
  if (header_->sleepers.load(std::memory_order_relaxed) != 0) {
    header_->wake.fetch_add(1, std::memory_order_release);
    futexWakeAll(header_->wake, FutexScope::Shared);
  }
  return PushStatus::Written;
}

void RingBuffer::wakeReaders() {
  header_->wake.fetch_add(1, std::memory_order_release);
  futexWakeAll(header_->wake, FutexScope::Shared);
}

std::uint32_t RingBuffer::epoch() const { return header_->epoch.load(std::memory_order_acquire); }
std::uint64_t RingBuffer::written() const { return header_->head.load(std::memory_order_acquire); }
std::uint32_t RingBuffer::sleepingReaders() const { return header_->sleepers.load(std::memory_order_acquire); }

RingReader::RingReader(const RingBuffer& ring)
    : header_(ring.header_), slots_(ring.slots_), mask_(ring.mask_), stride_(ring.stride_),
      sample_size_(ring.sample_size_), next_(ring.written()) {}

std::optional<SampleInfo> RingReader::read(std::uint64_t index, void* out, std::uint64_t* seen_seq) const {
  SlotHeader& slot = slotAt(slots_, stride_, mask_, index);
  const std::uint64_t before = slot.seq.load(std::memory_order_acquire);
  *seen_seq = before;
  if (before != 2 * index + 2) return std::nullopt;
  const std::uint32_t epoch = slot.epoch.load(std::memory_order_relaxed);
  loadWords(out, wordsOf(slot), sample_size_);
  std::atomic_thread_fence(std::memory_order_acquire);  // the copy before the second look
  const std::uint64_t after = slot.seq.load(std::memory_order_relaxed);
  *seen_seq = after;
  if (after != before) return std::nullopt;  // overwritten while copied: the copy is torn
  return SampleInfo{index, epoch};
}

std::optional<SampleInfo> RingReader::pop(void* out) {
  const std::uint64_t capacity = mask_ + 1;
  for (;;) {
    std::uint64_t seq = 0;
    if (auto got = read(next_, out, &seq)) {
      ++next_;
      return got;
    }
    if (seq < 2 * next_ + 2) return std::nullopt;  // not written yet, or being written
    // Lapped: the slot holds (or is being given) sample `newer`. The oldest sample still valid
    // is the one after it in that slot's previous round, or head - capacity when the writer
    // rests. Always forward, whatever the shared words say.
    const std::uint64_t newer = (seq - 1) / 2;
    const std::uint64_t head = header_->head.load(std::memory_order_acquire);
    std::uint64_t to = newer + 1 > capacity ? newer + 1 - capacity : 0;
    to = std::max({to, head > capacity ? head - capacity : 0, next_ + 1});
    dropped_ += to - next_;
    next_ = to;
  }
}

std::optional<SampleInfo> RingReader::latest(void* out) {
  std::uint64_t head = header_->head.load(std::memory_order_acquire);
  for (;;) {
    if (head <= next_) return std::nullopt;
    std::uint64_t seq = 0;
    if (auto got = read(head - 1, out, &seq)) {
      dropped_ += head - 1 - next_;
      next_ = head;
      return got;
    }
    const std::uint64_t again = header_->head.load(std::memory_order_acquire);
    if (again == head) return std::nullopt;  // nothing whole to read now
    head = again;
  }
}

bool RingReader::available() const { return header_->head.load(std::memory_order_seq_cst) > next_; }

std::optional<FutexWaiter> RingReader::announceSleep() {
  if (available()) return std::nullopt;
  const std::uint32_t word = header_->wake.load(std::memory_order_acquire);
  header_->sleepers.fetch_add(1, std::memory_order_seq_cst);
  std::atomic_thread_fence(std::memory_order_seq_cst);  // announce, then the last look
  if (available()) {
    endSleep();
    return std::nullopt;
  }
  return FutexWaiter{&header_->wake, word, FutexScope::Shared};
}

void RingReader::endSleep() { header_->sleepers.fetch_sub(1, std::memory_order_release); }

bool RingReader::wait(std::chrono::nanoseconds timeout) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::min<std::chrono::nanoseconds>(timeout, std::chrono::hours(24 * 365));
  for (;;) {
    const std::optional<FutexWaiter> sleep = announceSleep();
    if (!sleep) return true;
    if (Clock::now() < deadline) futexWait(*sleep->word, sleep->expected, &deadline, FutexScope::Shared);
    endSleep();
    if (available()) return true;
    if (sleep->word->load(std::memory_order_acquire) != sleep->expected) return false;  // wakeReaders()
    if (Clock::now() >= deadline) return false;
  }
}

}  // namespace keel::runtime::ipc
