// Session: the control region one `keel run` shares with the component processes it starts
// (docs/isolation.md; decision 0011). One memfd holds:
// - the supervisor lock, a robust mutex held by keel run's main thread for the whole run: when
//   keel run dies, every host's watcher thread gets it (OwnerDied), stops the actuators it hosts
//   and exits;
// - per <process>, a ProcessBlock: the role lock held by its active host's main thread (the
//   standbys sleep on it: the kernel wakes one when the active dies), the command word keel run
//   writes for every host of the process, and one slot per host process: its life lock (held by
//   the host's main thread: keel run's watcher for that host wakes when it dies), state and pid;
// - per connection between processes, the word saying its ring is laid out (the ring's memfd is
//   created empty by keel run and sized by the writing side, which knows sizeof(T)), and the
//   reading side's position in it;
// - per instance in a component process, a double-buffered checkpoint area (its critical()
//   memory as of its last checkpoint, what a standby or a respawned process resumes with).
// Every index (process, ring, checkpoint) is the plan's, computed the same way by keel run and
// by each host from the same profiles; a hash of the plan's shape guards that.
// Thread-safety: the region is shared; each word says who writes it.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "keel/result.hpp"
#include "runtime/ipc/robust_mutex.hpp"
#include "runtime/ipc/shared_memory.hpp"

namespace keel::runtime::ipc {

inline constexpr std::size_t kHostSlots = 12;                            // per process: active, standbys, replacements
inline constexpr std::size_t kCheckpointBytes = std::size_t{64} * 1024;  // per instance and buffer
inline constexpr std::size_t kHostMessageBytes = 1024;                   // a host's error text

enum class HostState : std::uint32_t {
  Free,      // no process in this slot
  Starting,  // being spawned (written by keel run)
  Loading,   // holds its life lock; loading and initialising its components
  Standby,   // loaded, initialised, asleep on the role lock
  Active,    // holds the role lock and runs its components
  Exited,    // left on request (a stop, the end of the run)
  Failed,    // could not start: `message` says why
};
std::string_view toString(HostState s);

enum class Command : std::uint32_t {
  Run,        // go on
  Stop,       // the run ends: stop the components, exit
  Emergency,  // run the actuators' onEmergencyStop now (the emergency is latched)
};

/// One host process of a <process>. Written by that host, except `state` Free/Starting and
/// `pid` (keel run, before it spawns).
struct HostSlot {
  RobustMutex life;                     // held by the host's main thread while it lives
  std::atomic<std::uint32_t> state{0};  // HostState; a shared futex word (bumped per change)
  std::atomic<std::int32_t> pid{0};
  std::atomic<std::int64_t> active_ns{0};     // when it became active (steady ns)
  std::atomic<std::int64_t> woke_ns{0};       // when it took the role from a dead holder
  std::atomic<std::int64_t> beat_ns{0};       // its heartbeat while active (processHeartbeatNs)
  std::atomic<std::int64_t> first_run_ns{0};  // its first successful onExecute once active
  std::atomic<std::uint32_t> restored{0};     // instances whose checkpoint it restored
  std::atomic<std::uint32_t> message_len{0};  // of `message`, written before state Failed
  char message[kHostMessageBytes];
};

struct ProcessBlock {
  RobustMutex role;                                // held by the active host's main thread
  std::atomic<std::uint32_t> command{0};           // Command, written by keel run; a shared futex word
  std::atomic<std::uint32_t> changes{0};           // a shared futex word: bumped at every slot state change
  std::atomic<std::uint32_t> emergencies_done{0};  // bumped by the active host after its emergency stop
  // Set by a host that found keel run gone, before its emergency stop and exit: a standby that
  // wakes with the role afterwards leaves instead of taking over (the run is over).
  std::atomic<std::uint32_t> supervisor_lost{0};
  HostSlot slots[kHostSlots];
};

/// The critical() memory of one instance as of its last checkpoint: two buffers, the newer one
/// published by `seq` (odd: buffer 1, even and non-zero: buffer 0). Written by the one active
/// host's component thread, which fills the unpublished buffer: a kill mid-copy leaves the
/// published one whole.
struct CheckpointArea {
  std::atomic<std::uint64_t> seq{0};  // checkpoints published; 0: none yet
  std::int64_t t_ns[2] = {0, 0};
  std::uint64_t bytes[2] = {0, 0};
  std::byte data[2][kCheckpointBytes];
};

/// Writes one checkpoint (a copy per critical region) into `area` and publishes it; false
/// (nothing written) when it needs more than kCheckpointBytes. The layout: the count of
/// regions, each one's length, their bytes.
bool publishCheckpoint(CheckpointArea& area, const std::vector<std::vector<std::byte>>& copies, std::int64_t t_ns);
/// Maps into this process the pages of `area` a checkpoint of `copies`' sizes uses, in both
/// buffers, by reading them: a standby reads the checkpoint at its takeover without page faults.
void prefaultCheckpoint(const CheckpointArea& area, const std::vector<std::vector<std::byte>>& copies);
/// Reads the published checkpoint into `copies` (resized to it) if it has regions of exactly
/// `lengths`; its time, or nothing when there is none or its shape differs.
std::optional<std::int64_t> readCheckpoint(const CheckpointArea& area, const std::vector<std::size_t>& lengths,
                                           std::vector<std::vector<std::byte>>& copies);

/// The run's one log, written by every process (decision 0011 §6): each line goes to an offset
/// reserved under a robust lock, after it was staged here, in the writer's own stage; a line
/// whose writer died before it was whole on disk is written again from its stage by a survivor.
inline constexpr std::size_t kLogStageBytes = 4096;  // longer lines are written, not staged
inline constexpr std::uint64_t kNoOffset = ~std::uint64_t{0};

struct LogStage {
  std::atomic<std::uint64_t> offset{kNoOffset};  // reserved for the staged line; none: nothing pending
  std::atomic<std::uint32_t> length{0};
  char line[kLogStageBytes];
};

struct LogArena {
  RobustMutex lock;                    // held while a reservation is made
  std::atomic<std::uint64_t> tail{0};  // the end of the last reservation
  std::uint64_t stage_count = 0;       // written once, at creation
};

/// Stage `i` of `arena` (they follow it in the session: [0] keel run's, then kHostSlots per
/// process, logParticipant()); `i` below arena.stage_count.
LogStage& logStage(LogArena& arena, std::size_t i);

/// A log participant's stage index: keel run (process index none) or a host's slot.
std::size_t logParticipant(std::optional<std::size_t> process, std::size_t slot);

struct SessionShape {
  std::size_t processes = 0;
  std::size_t rings = 0;        // connections between processes
  std::size_t checkpoints = 0;  // instances in component processes
  std::uint64_t plan_hash = 0;  // of what the indices index
};

inline constexpr std::uint32_t kRingPending = 0, kRingReady = 1, kRingAbandoned = 2;

class Session {
 public:
  /// keel run: a new region of `shape`, every lock initialised.
  static Result<Session> create(const SessionShape& shape);
  /// A host: maps the region behind `fd` (owned from here) and checks it is a session of this
  /// shape (the same plan).
  static Result<Session> adopt(int fd, const SessionShape& shape);

  RobustMutex& supervisor();
  std::atomic<std::uint64_t>& faultIds();  // the run's fault ids: every process counts here
  std::atomic<std::int64_t>& logEpoch();   // keel run's log epoch (steady ns): every t_ns counts from it
  ProcessBlock& process(std::size_t i);
  /// kRingPending, then kRingReady once the ring's memfd is laid out (its writer), or
  /// kRingAbandoned when the run stops before that (keel run): a reader waits on this word.
  std::atomic<std::uint32_t>& ringReady(std::size_t i);
  /// keel run, stopping: every ring not laid out yet never will be; its readers stop waiting.
  void abandonRings();
  /// The next sample the reading side (whichever process of it is active) will deliver: where
  /// a reader taking over resumes.
  std::atomic<std::uint64_t>& ringConsumed(std::size_t i);
  CheckpointArea& checkpoint(std::size_t i);
  LogArena& log();  // stages for 1 + processes × kHostSlots participants
  const SessionShape& shape() const { return shape_; }
  const SharedMemory& memory() const { return memory_; }

 private:
  Session(SharedMemory memory, const SessionShape& shape);
  SharedMemory memory_;
  SessionShape shape_;
};

/// A host's error text for keel run (why it could not start), truncated to kHostMessageBytes;
/// written before the state Failed is published.
void setMessage(HostSlot& slot, std::string_view text);
std::string messageOf(const HostSlot& slot);

/// Sets `slot`'s state and wakes whoever waits on its process block's `changes`.
void publishState(ProcessBlock& block, HostSlot& slot, HostState state);
/// Writes `command` for every host of `block` and wakes them.
void publishCommand(ProcessBlock& block, Command command);

}  // namespace keel::runtime::ipc
