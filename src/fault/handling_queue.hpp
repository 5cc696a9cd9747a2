// The fault manager's own thread and the queue that feeds it: what needs the whole picture
// (a cold replacement off the component's thread, fault stop, emergency stop, the log) is
// handed over here without allocating — one copy of the report into a fixed ring — and the
// thread wakes only when told to (a recovery queues its report silently: nothing but the
// recovery may be on its path). A full ring makes the reporter wait; no fault is dropped.
// Without a running thread (not started, stopping) an item is processed on the caller's.
// Thread-safety: enqueue/drain from any thread; start/stop from the owner's.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "fault/report.hpp"
#include "runtime/wake_signal.hpp"

namespace keel::fault {

struct HandlingItem {
  // Report: carry on handling; Recovered: log it; CheckInterrupted: verify that a hung
  // callback came back when interrupted, else abandon its executor.
  enum class Type : std::uint8_t { Report, Recovered, CheckInterrupted } type = Type::Report;
  FaultReport report;
};

class HandlingQueue {
 public:
  using Process = std::function<void(HandlingItem&)>;
  static constexpr std::size_t kCapacity = 512;

  explicit HandlingQueue(Process process, std::size_t capacity = kCapacity);
  ~HandlingQueue();
  HandlingQueue(const HandlingQueue&) = delete;
  HandlingQueue& operator=(const HandlingQueue&) = delete;

  /// Starts the thread (SCHED_FIFO one below the watchdog when permitted).
  void start();
  /// Processes what is queued, then ends the thread; later items are processed by their callers.
  void stop();
  /// Waits (at most 10 s) until everything queued so far has been processed.
  void drain();

  /// Hands `report` over (one copy into its slot), waking the thread if `wake`; processes it
  /// here when the thread does not take items or this is the thread.
  void enqueue(HandlingItem::Type type, const FaultReport& report, bool wake);

  /// From now on the thread's sleep has its safety-net timeout, so that a report queued without
  /// a wake-up (a recovery's) is taken even if nothing wakes the thread after it. Called once
  /// the components run; wakes the thread once, here, rather than in a recovery's hot path.
  void armSafetyNet();

  bool onThread() const { return std::this_thread::get_id() == thread_id_.load(); }
  bool running() const { return thread_id_.load() != std::thread::id{}; }

 private:
  void run();

  Process process_;
  std::thread thread_;
  std::atomic<std::thread::id> thread_id_{};
  runtime::WakeSignal signal_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::vector<HandlingItem> ring_;  // fixed capacity: enqueue never allocates
  std::size_t head_ = 0, size_ = 0;
  bool accepting_ = false;  // the thread runs and takes items (guarded by mutex_)
  std::atomic<std::uint64_t> enqueued_{0}, processed_{0};
  // Set by armSafetyNet() once the components run: from then on the thread's sleep has its
  // safety-net timeout; until then it sleeps until woken, so a process whose components never
  // run (a standby host) never wakes it. Never set by a report: waking this real-time thread
  // between a recovery and the recovered component's first step would delay that step by the
  // thread's whole logging of the fault (it preempts the task's CPU).
  std::atomic<bool> safety_net_armed_{false};
};

}  // namespace keel::fault
