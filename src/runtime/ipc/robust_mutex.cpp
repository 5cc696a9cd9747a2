#include "runtime/ipc/robust_mutex.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <system_error>

namespace keel::runtime::ipc {
namespace {

Error mutexError(const char* call, int err) {
  return fail(fmt::format("robust mutex: {}: {}", call, std::generic_category().message(err)));
}

}  // namespace

Result<void> RobustMutex::init() {
  pthread_mutexattr_t attr;
  if (int err = pthread_mutexattr_init(&attr)) return mutexError("pthread_mutexattr_init", err);
  int err = pthread_mutexattr_setpshared(&attr, PTHREAD_PROCESS_SHARED);
  if (!err) err = pthread_mutexattr_setrobust(&attr, PTHREAD_MUTEX_ROBUST);
  if (!err) err = pthread_mutexattr_settype(&attr, PTHREAD_MUTEX_ERRORCHECK);
  if (!err) err = pthread_mutex_init(&mutex_, &attr);
  pthread_mutexattr_destroy(&attr);
  if (err) return mutexError("pthread_mutex_init", err);
  return {};
}

Result<LockStatus> RobustMutex::lock() { return locked(pthread_mutex_lock(&mutex_), "pthread_mutex_lock"); }

Result<LockStatus> RobustMutex::tryLock() {
  const int rc = pthread_mutex_trylock(&mutex_);
  if (rc == EBUSY) return LockStatus::Busy;
  return locked(rc, "pthread_mutex_trylock");
}

Result<void> RobustMutex::unlock() {
  if (int err = pthread_mutex_unlock(&mutex_)) return mutexError("pthread_mutex_unlock", err);
  return {};
}

Result<LockStatus> RobustMutex::locked(int rc, const char* call) {
  if (rc == 0) return LockStatus::Acquired;
  if (rc != EOWNERDEAD) return mutexError(call, rc);
  // We own it now; marked consistent, it works as before for every process. (Unlocking it
  // without this would make it unusable: ENOTRECOVERABLE for everyone after.)
  if (int err = pthread_mutex_consistent(&mutex_)) return mutexError("pthread_mutex_consistent", err);
  return LockStatus::OwnerDied;
}

}  // namespace keel::runtime::ipc
