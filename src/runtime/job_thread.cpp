#include "runtime/job_thread.hpp"

#include <future>
#include <utility>

namespace keel::runtime {

JobThread::JobThread() : thread_([this] { run(); }) {}

JobThread::~JobThread() { stop(); }

void JobThread::post(std::function<void()> job) {
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void JobThread::drain() {
  if (isCurrent()) return;
  std::promise<void> ran;
  auto reached = ran.get_future();
  {
    std::lock_guard lock(mutex_);
    if (ended_) return;
    jobs_.emplace_back([&ran] { ran.set_value(); });
  }
  wake_.notify_one();
  reached.wait();
}

void JobThread::stop() {
  {
    std::lock_guard lock(mutex_);
    done_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable() && !isCurrent()) thread_.join();
}

void JobThread::run() {
  id_.store(std::this_thread::get_id(), std::memory_order_release);
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return done_ || !jobs_.empty(); });
    if (jobs_.empty()) {  // stopped, and nothing left to run
      ended_ = true;
      return;
    }
    auto job = std::move(jobs_.front());
    jobs_.pop_front();
    lock.unlock();
    job();
    lock.lock();
  }
}

}  // namespace keel::runtime
