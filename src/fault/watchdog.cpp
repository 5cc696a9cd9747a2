#include "fault/watchdog.hpp"

#include <fmt/format.h>
#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>

#include <algorithm>
#include <cstring>
#include <system_error>

#include "runtime/component_core.hpp"
#include "runtime/fault_detail.hpp"
#include "runtime/injection.hpp"

namespace keel::fault {

Watchdog::Watchdog(std::vector<WatchedComponent> watched, FaultManager& manager, runtime::Warn warn, bool realtime)
    : watched_(std::move(watched)), episodes_(watched_.size()), manager_(manager), warn_(std::move(warn)),
      realtime_(realtime) {
  for (const auto& w : watched_) poll_ns_ = std::min(poll_ns_, std::max<std::int64_t>(w.timeout_ns / 2, 100'000));
}

Watchdog::~Watchdog() { stop(); }

void Watchdog::start() {
  if (watched_.empty() || thread_.joinable()) return;
  thread_ = std::thread([this] { run(); });
}

void Watchdog::stop() {
  if (!thread_.joinable()) return;
  stop_.store(true, std::memory_order_release);
  signal_.notify();
  thread_.join();
}

void Watchdog::report(Component& c, const WatchedComponent& w, std::int64_t now, const char* what, double late_ms) {
  FaultEvent ev;
  ev.kind = FaultKind::Heartbeat;
  ev.t_ns = now;
  FaultEvent::copyInto(ev.component, c.instanceName());
  runtime::formatDetail(ev, "{} for {:.3f} ms (heartbeat timeout {:.3f} ms)", what, late_ms, w.timeout_ns / 1e6);
  manager_.report(c, ev, "watchdog");
}

std::int64_t Watchdog::check(const WatchedComponent& w, Episode& e, std::int64_t now) {
  Component& c = *w.component->load(std::memory_order_acquire);
  if (c.state() != State::Active) return now + poll_ns_;
  const auto& core = runtime::coreOf(c);
  if (std::int64_t since = core.watch.callback_since_ns.load(std::memory_order_relaxed); since != 0) {
    const std::int64_t deadline = since + w.timeout_ns;
    if (now < deadline) return deadline;
    if (e.reported_since != since) {
      e.reported_since = since;
      report(c, w, now, "a callback has not returned", (now - since) / 1e6);
    }
    return now + poll_ns_;
  }
  if (w.period_ns == 0) return now + poll_ns_;
  const std::int64_t beat = core.watch.last_beat_ns.load(std::memory_order_relaxed);
  if (beat == 0) return now + poll_ns_;  // not executed yet
  const std::int64_t deadline = beat + w.period_ns + w.timeout_ns;
  if (now < deadline) return deadline;
  if (e.reported_beat != beat) {
    e.reported_beat = beat;
    report(c, w, now, "not executed", (now - beat) / 1e6);
  }
  return now + poll_ns_;
}

void Watchdog::run() {
  pthread_setname_np(pthread_self(), "keel-watchdog");
  prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0);
  sched_param sp{};
  sp.sched_priority = sched_get_priority_max(SCHED_FIFO);
  if (!realtime_) {
  } else if (int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp); err != 0 && warn_)
    warn_(fmt::format("watchdog: SCHED_FIFO refused ({}); hang detection runs at normal priority",
                      std::generic_category().message(err)));
  while (!stop_.load(std::memory_order_acquire)) {
    const std::int64_t now = runtime::steadyNs();
    std::int64_t next = now + poll_ns_;
    for (std::size_t i = 0; i < watched_.size(); ++i) next = std::min(next, check(watched_[i], episodes_[i], now));
    signal_.waitUntil(runtime::WakeSignal::Clock::time_point(std::chrono::nanoseconds(next)));
  }
}

}  // namespace keel::fault
