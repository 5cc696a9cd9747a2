// A thread of its own for work that must not run on the thread that asks for it (a spawn that
// waits for a child, an emergency stop that may take its containment bound): the jobs posted
// run one at a time, in the order posted.
// Thread-safety: post(), drain() and isCurrent() from any thread; stop() once, from one thread.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

namespace keel::runtime {

class JobThread {
 public:
  JobThread();
  /// stop().
  ~JobThread();
  JobThread(const JobThread&) = delete;
  JobThread& operator=(const JobThread&) = delete;

  /// Queues `job` behind those posted before it.
  void post(std::function<void()> job);
  /// Whether the caller is this thread (a job that must not wait for a later one).
  bool isCurrent() const { return std::this_thread::get_id() == id_.load(std::memory_order_acquire); }
  /// Returns once every job posted before the call has run (at once on the thread itself, or
  /// once the thread has ended): for an owner of posted jobs that refer to it, before it goes.
  void drain();
  /// Runs what was posted, then ends the thread and joins it. Idempotent.
  void stop();

 private:
  void run();
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool done_ = false;
  bool ended_ = false;  // run() returned: nothing posted runs any more
  // The thread's id, stored by the thread itself: thread_.get_id() would race with a join.
  std::atomic<std::thread::id> id_{};
  std::thread thread_;  // last: started once the members it uses are
};

}  // namespace keel::runtime
