// RobustMutex: a process-shared, robust pthread mutex that lives in shared memory, keel's way of
// learning that a process died (decision 0011 §1): when the thread holding it dies, the kernel
// marks it and wakes one waiter, whose lock() reports OwnerDied (already made consistent again:
// the caller owns it and repairs what it guards). Used for the process and role locks of the
// host processes and for every ring's writer lock (runtime/ipc/ring.hpp).
//
// THE RULE: the kernel tracks robust locks per *thread* (each thread's robust list, walked when
// that thread exits). A lock whose release is to signal a process's death must therefore be held
// by a thread that never ends while the process lives — its main thread, which must never
// pthread_exit, or a thread that parks rather than end (a standby's role, supervision/process_host.hpp):
// a lock held by a thread is released, as if the process died, when that thread ends. Keep the
// memory mapped while holding it: the kernel cannot mark a lock it can no longer reach, and its
// waiters then sleep forever.
//
// Error-checking type: relocking by the owner and unlocking by another thread are errors, not a
// deadlock or a silent release. Thread-safety: any thread of any process mapping it.
#pragma once

#include <pthread.h>

#include "keel/result.hpp"

namespace keel::runtime::ipc {

enum class LockStatus {
  Acquired,   // locked, its previous owner had unlocked it
  OwnerDied,  // locked, and its previous owner had died holding it: repair what it guards
  Busy,       // tryLock only: another thread holds it
};

class RobustMutex {
 public:
  /// Trivial: the object is memory in a shared region; init() it once before anyone locks it.
  RobustMutex() = default;
  ~RobustMutex() = default;  // nothing to release: a region outlives any one process's view
  RobustMutex(const RobustMutex&) = delete;
  RobustMutex& operator=(const RobustMutex&) = delete;

  /// Initialises it in place (process-shared, robust, error-checking). Called once, by the
  /// process that creates the region, before the region is shared.
  Result<void> init();

  /// Blocks until locked. An error only for a broken mutex: relocked by its owner, or its
  /// memory overwritten (a region's memory is writable by every process mapping it).
  Result<LockStatus> lock();
  /// Locks if free, or reports Busy at once.
  Result<LockStatus> tryLock();
  /// Unlocks; an error when the calling thread does not hold it.
  Result<void> unlock();

 private:
  Result<LockStatus> locked(int rc, const char* call);

  pthread_mutex_t mutex_;
};

}  // namespace keel::runtime::ipc
