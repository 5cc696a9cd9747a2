// Service calls (keel/service_port.hpp): run on the provider's executor, or inline under the
// provider's lock when it is passive or the caller is already on its executor.
#include <fmt/format.h>

#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include "keel/service_port.hpp"
#include "runtime/checkpoint.hpp"
#include "runtime/clock.hpp"
#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"
#include "runtime/invoke.hpp"

namespace keel::runtime {
namespace {

struct Completion {
  std::mutex mutex;
  std::condition_variable cv;
  bool done = false;
  std::string why;
};

std::string runCall(Component& provider, const std::string& port, detail::ServiceCall& call) {
  if (provider.state() != State::Active)
    return fmt::format("service '{}' of '{}': provider is {}, not Active", port, provider.instanceName(),
                       toString(provider.state()));
  GuardOutcome out = guarded(
      [&call] {
        call.run();
        return ReturnCode::Ok;
      },
      &provider, &coreOf(provider).fault.interrupt);
  finishCall(provider, out, Callback::Service);  // a fault it raised meanwhile is handled now
  if (out.ok()) return {};                       // ... but the call itself returned its result
  FaultEvent ev;
  out.describe(ev, "service call");
  return fmt::format("service '{}' of '{}' faulted: {}", port, provider.instanceName(), ev.detailText());
}

}  // namespace
}  // namespace keel::runtime

std::string keel::detail::invokeService(Component& provider, const std::string& port,
                                        const std::shared_ptr<ServiceCall>& call, std::chrono::nanoseconds timeout) {
  using namespace keel::runtime;
  auto& core = coreOf(provider);
  Executor* ex = core.executor.load(std::memory_order_acquire);
  if (ex == nullptr || ex->onThisThread()) {
    std::unique_lock lock(core.passive_mutex, std::defer_lock);
    const auto give_up = std::chrono::steady_clock::now() + timeout;
    while (!lock.try_lock() && std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::microseconds(50));
    if (!lock.owns_lock())
      return fmt::format("service '{}' of '{}': timed out after {} ms waiting for the provider", port,
                         provider.instanceName(), timeout.count() / 1e6);
    std::string why = runCall(provider, port, *call);
    // A passive provider's cycle boundary: between two calls, under its lock (docs/fault-handling.md).
    if (ex == nullptr && why.empty() && provider.state() == State::Active) checkpointIfDue(core, steadyNs());
    return why;
  }
  if (provider.state() != State::Active)
    return fmt::format("service '{}' of '{}': provider is {}, not Active", port, provider.instanceName(),
                       toString(provider.state()));
  auto done = std::make_shared<Completion>();
  ex->post([&provider, port, call, done] {
    std::string why = runCall(provider, port, *call);
    std::lock_guard lock(done->mutex);
    done->why = std::move(why);
    done->done = true;
    done->cv.notify_all();
  });
  std::unique_lock lock(done->mutex);
  if (!done->cv.wait_for(lock, timeout, [&] { return done->done; }))
    return fmt::format("service '{}' of '{}': no answer within {} ms", port, provider.instanceName(),
                       timeout.count() / 1e6);
  return done->why;
}
