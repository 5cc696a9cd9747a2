// Executors decide *when* components run (Orocos's activity; OPRoS's executor). The only place
// keel makes threads for components:
//  - Periodic: one thread; every period (absolute-time sleeps, sub-millisecond allowed) runs
//    onExecute of each member in declared order, then onUpdated of each. One member is a
//    component with its own executor; several are the paper's task.
//  - Aperiodic: one thread that blocks until an input data port of a member receives a value,
//    then runs onExecute/onUpdated; never spins.
// Events are delivered to onEvent on this thread as they arrive; lifecycle transitions of the
// members (start at thread start, stop at thread end) and service calls run here too, so one
// component's callbacks never overlap. Overruns of the period are counted.
// Thread-safety: start/requestStop/join from the engine; wake/post from any thread.
#pragma once

#include <pthread.h>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "keel/component.hpp"
#include "keel/detail/enums.hpp"
#include "runtime/futex.hpp"
#include "runtime/wake_signal.hpp"
#include "runtime/warning.hpp"

namespace keel::runtime {

/// Values that reach an executor's members from another process (supervision/crossing.hpp's rings).
/// The executor sleeps on them along with its own wake-ups and moves what arrived into the
/// ports itself, on its own thread, before its members run: one wake from the writer's push to
/// the component's step. Its calls come from the executor's thread only.
class ExternalInput {
 public:
  virtual ~ExternalInput() = default;
  /// Announces the executor's sleep and gives the futex word to sleep on, or nothing (and no
  /// announcement) when a value is there already.
  virtual std::optional<FutexWaiter> announceSleep() = 0;
  /// Ends an announcement, once awake.
  virtual void endSleep() = 0;
  /// Moves every value that arrived into its port; true when there was one.
  virtual bool drain() = 0;
};

/// The end of a run in two steps, so that no component's last cycle calls one already stopped:
/// every executor holding the barrier ends its cycles, still answering calls meanwhile, and none
/// stops its members (onStop) before all have ended theirs, or the engine has let them go on
/// (one is stuck in a callback). Thread-safe.
class StopBarrier {
 public:
  /// An executor that cycles (Executor::holdStop).
  void enter() { cycling_.fetch_add(1, std::memory_order_acq_rel); }
  /// It cycles no more; once per enter().
  void leave() { cycling_.fetch_sub(1, std::memory_order_acq_rel); }
  /// True once every executor has left, or after release().
  bool clear() const {
    return released_.load(std::memory_order_acquire) || cycling_.load(std::memory_order_acquire) <= 0;
  }
  /// Waits for clear() until `deadline`; false if it was not by then.
  bool waitClear(std::chrono::steady_clock::time_point deadline) const;
  /// Lets the executors waiting on it go on, whoever still cycles.
  void release() { released_.store(true, std::memory_order_release); }

 private:
  std::atomic<int> cycling_{0};
  std::atomic<bool> released_{false};
};

enum class ExecutorKind { Periodic, Aperiodic };

struct ExecutorConfig {
  std::string name;
  ExecutorKind kind = ExecutorKind::Periodic;
  std::chrono::nanoseconds period{std::chrono::milliseconds(100)};
  int priority = 0;  // 0: leave as is
  SchedPolicy policy = SchedPolicy::Other;
};

struct ExecutorStats {
  std::uint64_t cycles = 0;
  std::uint64_t overruns = 0;  // cycles that ended after the next release time
};

class Executor {
 public:
  explicit Executor(ExecutorConfig config, Warn warn = {});
  ~Executor();
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  /// Adds a member (before start); it runs in the order added.
  void add(Component& c);
  const std::vector<Component*>& members() const { return members_; }
  const ExecutorConfig& config() const { return config_; }

  /// Adds an input from another process (before start); the executor drains it, and wakes
  /// when it has a value, until its thread exits. At most kMaxExternalInputs.
  void addInput(ExternalInput& input);
  const std::vector<ExternalInput*>& inputs() const { return inputs_; }
  static constexpr std::size_t kMaxExternalInputs = kFutexWaitAnyMax - 1;

  /// Starts the thread; it starts its members (onStart) and returns once they have. With
  /// `adopt`, the members are taken over as they are (already started by another executor).
  void start(bool adopt = false);
  /// As start(), without waiting for the members' onStart (waitStarted() waits). Any thread,
  /// the executor's own included (from its `before_park`).
  void release();
  /// Returns once the members have started (or the thread has exited).
  void waitStarted() const;
  /// Before start(): once its members have started, the executor waits for `*go` to be nonzero
  /// (notified) before its first cycle. The engine starts every executor so and then lets them
  /// all go: no component's first onExecute finds another not yet started (a service it calls
  /// in its first cycle, OPRoS's helloworld does, is Active). `go` outlives the executor.
  void holdFirstCycle(std::atomic<std::uint32_t>* go) { go_ = go; }
  /// Before start(): at its end the executor waits, answering calls, until `barrier` is clear
  /// before it stops its members. Enters the barrier now; the executor leaves it once, when its
  /// cycles end or it is abandoned. `barrier` outlives the executor.
  void holdStop(StopBarrier& barrier) {
    stop_barrier_ = &barrier;
    barrier.enter();
  }
  /// Starts the thread ahead, set up (name, policy, stack) and parked before its members start:
  /// start() then only lets it go on (a standby host's takeover creates no thread). A parked
  /// thread asked to stop exits without starting or stopping its members.
  /// `before_park` runs on the thread, set up, before it parks (it may release() it: the thread
  /// then goes on at once); `at_exit` runs on the thread as it ends, whichever way it ends.
  void prepare(std::function<void()> before_park = {}, std::function<void()> at_exit = {});
  /// Gives up a thread stuck in a callback that could not be interrupted: it is asked to stop,
  /// and should it ever come back it touches no member again (they run on another executor).
  void abandon();
  bool abandoned() const { return abandoned_.load(std::memory_order_acquire); }
  /// Asks the thread to finish its cycle, stop its members (onStop) and exit.
  void requestStop();
  /// Waits for the thread to exit; false if it did not within `timeout` (it is then left).
  bool join(std::chrono::nanoseconds timeout);

  /// Wakes the thread (input arrived, an event, mail).
  void wake() { signal_.notify(); }
  /// Runs `job` on this executor's thread, between callbacks.
  void post(std::function<void()> job);
  bool onThisThread() const { return std::this_thread::get_id() == thread_id_.load(); }
  /// Ends the hung callback running on this executor's thread, if its component's `interrupt`
  /// flag is set (runtime/guard.hpp interruptThread).
  void interrupt();
  /// Runs `c`'s onExecute now, outside the schedule: the step a component recovered between
  /// cycles still owes. Only on this executor's thread.
  bool runStep(Component& c) { return execute(c); }
  /// Puts `alternative` in `failed`'s place among the members (a fault's replacement). Only on
  /// this executor's thread (the members are iterated there without a lock).
  void replaceMember(Component& failed, Component& alternative);

  ExecutorStats stats() const {
    return {cycles_.load(std::memory_order_relaxed), overruns_.load(std::memory_order_relaxed)};
  }
  /// steady-clock ns of the last completed cycle (the watchdog's heartbeat).
  std::int64_t lastCycleNs() const { return last_cycle_ns_.load(std::memory_order_relaxed); }

 private:
  void threadMain();
  void run();  // the thread's life between its setup and its exit
  void setUpThread();
  void runPeriodic();
  void runAperiodic();
  void cycle();
  bool execute(Component& c);   // one onExecute with its deadline check; true when it succeeded
  void serviceBetweenCycles();  // mail and events
  /// Sleeps until woken, `deadline` (null: for ever) or a value from another process; true when
  /// woken or a value came (the notification consumed), false at the deadline.
  bool sleepUntil(const std::chrono::steady_clock::time_point* deadline);
  void drainInputs();
  void runMail();
  void leaveStopBarrier();
  void waitStopBarrier();  // answering calls meanwhile

  ExecutorConfig config_;
  Warn warn_;
  std::vector<Component*> members_;
  std::vector<ExternalInput*> inputs_;
  std::vector<FutexWaiter> sleep_words_;  // sleepUntil's, reserved once
  std::thread thread_;
  std::atomic<std::thread::id> thread_id_{};
  std::atomic<pthread_t> native_{};
  WakeSignal signal_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> started_{false};
  std::atomic<bool> exited_{false};
  std::atomic<bool> abandoned_{false};
  bool adopt_ = false;
  bool prepared_ = false;              // set before the thread exists
  std::function<void()> before_park_;  // prepare()'s, likewise
  std::function<void()> at_exit_;
  std::atomic<std::uint32_t> gate_{1};        // 0 while a prepared thread is parked
  std::atomic<std::uint32_t>* go_ = nullptr;  // holdFirstCycle's; null: no wait
  StopBarrier* stop_barrier_ = nullptr;       // holdStop's; null: no wait
  std::atomic<bool> left_stop_barrier_{false};
  std::mutex mail_mutex_;
  std::vector<std::function<void()>> mail_;
  std::atomic<bool> has_mail_{false};
  std::atomic<std::uint64_t> cycles_{0};
  std::atomic<std::uint64_t> overruns_{0};
  std::atomic<std::int64_t> last_cycle_ns_{0};
};

}  // namespace keel::runtime
