// The robust mutex (runtime/ipc/robust_mutex.hpp): a holder killed -9 in another process is
// reported to the next locker as OwnerDied, made consistent; a process blocked on it wakes.
#include "runtime/ipc/robust_mutex.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>

#include "ipc_test_support.hpp"

namespace keel::runtime::ipc {
namespace {

using test::Child;

struct Control {
  RobustMutex mutex;
  std::atomic<int> holding{0};        // the holder has it
  std::atomic<int> about_to_lock{0};  // the waiter calls lock() next
  std::atomic<int> waiter_got{-1};    // the waiter's LockStatus, or 100 on an error
};

/// A child that locks the mutex in its main thread, says so, and sleeps until killed.
Child holder(test::SharedBlock<Control>& control) {
  Child child = Child::run([&control] {
    if (!control->mutex.lock()) return 2;
    control->holding = 1;
    for (;;) ::pause();
  });
  EXPECT_TRUE(test::eventually([&] { return control->holding.load() == 1; }));
  return child;
}

TEST(RobustMutex, TheNextLockerOfAMutexWhoseHolderWasKilledIsToldAndOwnsItConsistent) {
  test::SharedBlock<Control> control;
  ASSERT_TRUE(control->mutex.init());
  Child child = holder(control);
  EXPECT_EQ(control->mutex.tryLock().value(), LockStatus::Busy) << "held by the child";

  child.kill(SIGKILL);
  ASSERT_TRUE(test::killedBy(child.wait(), SIGKILL));

  EXPECT_EQ(control->mutex.tryLock().value(), LockStatus::OwnerDied);
  ASSERT_TRUE(control->mutex.unlock());
  EXPECT_EQ(control->mutex.lock().value(), LockStatus::Acquired) << "consistent again: a normal lock";
  EXPECT_TRUE(control->mutex.unlock());
}

TEST(RobustMutex, AProcessBlockedInLockWakesWithOwnerDiedWhenTheHolderIsKilled) {
  test::SharedBlock<Control> control;
  ASSERT_TRUE(control->mutex.init());
  Child child = holder(control);
  Child waiter = Child::run([&control] {
    control->about_to_lock = 1;
    auto got = control->mutex.lock();
    control->waiter_got = got ? static_cast<int>(*got) : 100;
    return got && control->mutex.unlock() ? 0 : 3;
  });
  ASSERT_TRUE(test::eventually([&] { return control->about_to_lock.load() == 1 && waiter.state() == 'S'; }))
      << "the waiter never blocked";
  EXPECT_EQ(control->waiter_got.load(), -1) << "the waiter got the lock while the holder held it";

  child.kill(SIGKILL);

  // Generous: the behaviour is that the kernel wakes it at all (decision 0011 measures the time).
  ASSERT_TRUE(test::eventually([&] { return control->waiter_got.load() != -1; }, std::chrono::seconds(5)))
      << "the waiter slept on after its holder's death";
  EXPECT_EQ(control->waiter_got.load(), static_cast<int>(LockStatus::OwnerDied));
  EXPECT_TRUE(test::exitedWith(waiter.wait(), 0));
  EXPECT_EQ(control->mutex.tryLock().value(), LockStatus::Acquired) << "the waiter left it consistent";
  EXPECT_TRUE(control->mutex.unlock());
}

TEST(RobustMutex, RelockingByTheOwnerAndUnlockingWhatIsNotHeldAreErrorsNotADeadlock) {
  test::SharedBlock<Control> control;
  ASSERT_TRUE(control->mutex.init());
  ASSERT_EQ(control->mutex.lock().value(), LockStatus::Acquired);

  auto again = control->mutex.lock();
  ASSERT_FALSE(again);
  EXPECT_EQ(again.error().message, "robust mutex: pthread_mutex_lock: Resource deadlock avoided");

  ASSERT_TRUE(control->mutex.unlock());
  auto twice = control->mutex.unlock();
  ASSERT_FALSE(twice);
  EXPECT_EQ(twice.error().message, "robust mutex: pthread_mutex_unlock: Operation not permitted");
}

}  // namespace
}  // namespace keel::runtime::ipc
