// The ring behind a port that crosses processes (decision 0011 §3): a slotted seqlock ring of
// fixed-size samples in one SharedMemory region, one writer at a time, any number of readers,
// each mapping the region in its own process. Used by the component hosts and `keel run` for
// every connection between processes; Ring<T> is the typed face of RingBuffer.
//
// - Slots: a power-of-two count, each a sequence word (2i+1 while sample i is written, 2i+2 once
//   committed), the epoch of its writer and the sample. A reader copies a slot and re-reads the
//   word: a sample overwritten meanwhile, or whose writer died halfway, is never returned.
// - Fencing: every push holds the ring's robust writer lock and checks the caller's epoch under
//   it; takeOver() bumps the epoch under the same lock. A writer fenced by a takeover is refused
//   (PushStatus::Fenced: it must stop writing), never visible, and never two writers at once. A
//   writer that died inside a push is repaired by the next one to lock (a committed sample is
//   kept, a half-written slot is written again). Epoch 0 is no writer: takeOver() comes first.
// - Readers: each keeps its cursor in its own memory; the writer never reads reader state, so a
//   dead or slow reader holds nothing up. A lapped reader skips to the oldest sample still in the
//   ring and counts the skipped ones as dropped (FIFO drops oldest); latest() reads the newest
//   (LAST, LIFO) and counts what it skipped the same way.
// - Waking: a reader announces that it sleeps and sleeps on the ring's futex word (shared, not
//   private); the writer makes the wake syscall only when a reader announced it. A reader that
//   died asleep costs the writer that syscall on every push, nothing else.
// - Trust: the geometry (sample size, slot count) is read and checked once when a process attaches
//   and kept in its own memory: a process scribbling over the region garbles samples, it cannot
//   make another process read or write outside the region.
//
// Thread-safety: push() and takeOver() from any thread of any process (the writer lock serialises
// them). A RingReader belongs to one thread; readers of different threads or processes are
// independent. Lock-free on the read side.
#pragma once

#include <array>
#include <bit>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "keel/result.hpp"
#include "runtime/futex.hpp"
#include "runtime/ipc/shared_memory.hpp"

namespace keel::runtime::ipc {

namespace detail {
struct RingHeader;  // the layout in shared memory (ring.cpp)
}

enum class PushStatus {
  Written,  // committed; readers see it
  Fenced,   // refused: the epoch given is not the ring's (a newer writer took over, or epoch 0)
};

/// What takeOver() made of the ring: the epoch to push with from now on.
struct TakeOver {
  std::uint32_t epoch = 0;
  bool writer_died = false;  // the writer lock's last holder died holding it (repaired)
};

/// Which sample a reader got: its position in the stream (0, 1, ...) and its writer's epoch.
struct SampleInfo {
  std::uint64_t index = 0;
  std::uint32_t epoch = 0;
};

class RingBuffer {
 public:
  /// The bytes a ring of `slots` samples of `sample_size` bytes needs (header and slots).
  static std::size_t bytesFor(std::size_t sample_size, std::size_t slots);
  /// A new ring of `slots` samples (a power of two) of `sample_size` bytes, both at most 2^24, in
  /// a region of its own named `name`.
  static Result<RingBuffer> create(const std::string& name, std::size_t sample_size, std::size_t slots);
  /// The same, laid out in `region` (at least bytesFor() bytes, not yet shared: whatever it
  /// held is overwritten).
  static Result<RingBuffer> create(SharedMemory region, std::size_t sample_size, std::size_t slots);
  /// This process's view of a ring another process created; checks the layout and the size of
  /// the samples this side expects.
  static Result<RingBuffer> attach(SharedMemory region, std::size_t sample_size);

  /// Makes the caller the ring's writer: under the writer lock (after the writer inside a push,
  /// if any, finished or died), bumps the epoch. Pushes with the previous epoch are refused.
  Result<TakeOver> takeOver();
  /// Writes one sample of sampleSize() bytes, if `epoch` is still the ring's.
  Result<PushStatus> push(std::uint32_t epoch, const void* sample);

  /// Wakes every reader asleep in wait() (which returns, perhaps with nothing to read): how a
  /// reader's own process stops its reading thread.
  void wakeReaders();

  std::uint32_t epoch() const;            // the current writer's, 0 before the first takeOver
  std::uint64_t written() const;          // samples committed so far
  std::uint32_t sleepingReaders() const;  // readers that announced they sleep in wait()
  std::size_t sampleSize() const { return sample_size_; }
  std::size_t slots() const { return static_cast<std::size_t>(mask_ + 1); }
  /// The region: its fd is what another process adopts to attach.
  const SharedMemory& memory() const { return memory_; }

 private:
  friend class RingReader;
  RingBuffer(SharedMemory region, std::size_t sample_size, std::size_t slots);
  Result<bool> lockWriter();  // true when its last holder died (the ring repaired)
  Result<void> unlockWriter();

  SharedMemory memory_;
  detail::RingHeader* header_ = nullptr;
  std::byte* slots_ = nullptr;
  std::uint64_t mask_ = 0;
  std::size_t stride_ = 0;
  std::size_t sample_size_ = 0;
};

/// One reader's cursor, in the reader's memory. Starts at the ring's end: it reads what is
/// pushed after it was made. Valid while the RingBuffer it reads lives.
class RingReader {
 public:
  explicit RingReader(const RingBuffer& ring);

  /// Copies the next sample (FIFO) into `out` (sampleSize() bytes), or returns nothing when
  /// there is none yet. `out` may be written even then.
  std::optional<SampleInfo> pop(void* out);
  /// Copies the newest sample into `out`, if newer than the last read; older unread ones are
  /// dropped. `out` may be written even when nothing is returned.
  std::optional<SampleInfo> latest(void* out);
  /// Sleeps until a sample is there to read, `timeout` (at most a year) passed or wakeReaders()
  /// was called; true when a sample is there. The only call of a reader that may enter the kernel.
  bool wait(std::chrono::nanoseconds timeout);

  /// For a thread that sleeps on this ring among other words (futexWaitAny): announces the
  /// sleep, so that the writer's next push wakes it, and gives the word and value to sleep on —
  /// or nothing, and announces nothing, when a sample is there to read already. Each
  /// announcement is ended with endSleep() once the thread is awake.
  std::optional<FutexWaiter> announceSleep();
  void endSleep();
  /// Whether a sample is there to read (the next pop() or latest() returns one, unless the
  /// writer laps the reader meanwhile).
  bool available() const;

  /// Moves the cursor to sample `next` (a reader taking over from another resumes where that
  /// one stopped); one older than the ring still holds is skipped over by the next pop().
  void seek(std::uint64_t next) { next_ = next; }

  std::uint64_t dropped() const { return dropped_; }  // samples lapped or skipped by latest()
  std::uint64_t next() const { return next_; }        // index of the next sample to read

 private:
  std::optional<SampleInfo> read(std::uint64_t index, void* out, std::uint64_t* seen_seq) const;

  detail::RingHeader* header_;
  std::byte* slots_;  // written by no reader: non-const for std::atomic_ref
  std::uint64_t mask_;
  std::size_t stride_;
  std::size_t sample_size_;
  std::uint64_t next_;
  std::uint64_t dropped_ = 0;
};

/// A ring of T: the sample size is sizeof(T), checked again by every process that attaches.
template <class T>
class Ring {
  static_assert(std::is_trivially_copyable_v<T>, "a sample crosses processes as bytes: T must be trivially copyable");

 public:
  class Reader {
   public:
    explicit Reader(const Ring& ring) : reader_(ring.buffer_) {}
    std::optional<T> pop(SampleInfo* info = nullptr) { return take(reader_.pop(bytes_.data()), info); }
    std::optional<T> latest(SampleInfo* info = nullptr) { return take(reader_.latest(bytes_.data()), info); }
    bool wait(std::chrono::nanoseconds timeout) { return reader_.wait(timeout); }
    std::uint64_t dropped() const { return reader_.dropped(); }

   private:
    std::optional<T> take(std::optional<SampleInfo> got, SampleInfo* info) {
      if (!got) return std::nullopt;
      if (info) *info = *got;
      return std::bit_cast<T>(bytes_);
    }
    RingReader reader_;
    std::array<std::byte, sizeof(T)> bytes_{};
  };

  /// A new ring of `slots` samples in a region of its own, named `name`.
  static Result<Ring> create(const std::string& name, std::size_t slots) {
    return wrap(RingBuffer::create(name, sizeof(T), slots));
  }
  /// This process's view of a ring of T created elsewhere (its region adopted from an fd).
  static Result<Ring> attach(SharedMemory region) { return wrap(RingBuffer::attach(std::move(region), sizeof(T))); }

  Result<TakeOver> takeOver() { return buffer_.takeOver(); }
  Result<PushStatus> push(std::uint32_t epoch, const T& value) { return buffer_.push(epoch, &value); }
  Reader reader() const { return Reader(*this); }
  const RingBuffer& buffer() const { return buffer_; }

 private:
  explicit Ring(RingBuffer buffer) : buffer_(std::move(buffer)) {}
  static Result<Ring> wrap(Result<RingBuffer> buffer) {
    if (!buffer) return buffer.error();
    return Ring(std::move(*buffer));
  }

  RingBuffer buffer_;
};

}  // namespace keel::runtime::ipc
