#include "fault/on_thread.hpp"

#include <atomic>
#include <memory>
#include <mutex>

#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"

namespace keel::fault {

bool onItsThread(Component& c, std::chrono::nanoseconds bound, const std::function<void()>& job) {
  auto& core = runtime::coreOf(c);
  runtime::Executor* ex = core.executor.load(std::memory_order_acquire);
  if (ex == nullptr) {
    std::unique_lock lock(core.passive_mutex, std::defer_lock);
    if (!waitFor(bound, [&] { return lock.try_lock(); })) return false;
    job();
    return true;
  }
  if (ex->onThisThread()) {
    job();
    return true;
  }
  auto done = std::make_shared<std::atomic<bool>>(false);
  ex->post([job, done] {
    job();
    done->store(true, std::memory_order_release);
  });
  return waitFor(bound, [&] { return done->load(std::memory_order_acquire); });
}

}  // namespace keel::fault
