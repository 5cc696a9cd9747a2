#include "runtime/executor.hpp"
#include "runtime/clock.hpp"

#include <fmt/format.h>
#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>

#include <cstdlib>
#include <cstring>
#include <system_error>

#include "runtime/checkpoint.hpp"
#include "runtime/component_core.hpp"
#include "runtime/execution_gate.hpp"
#include "runtime/fault_detail.hpp"
#include "runtime/guard.hpp"
#include "runtime/invoke.hpp"

namespace keel::runtime {

namespace {
bool stalled(detail::ComponentCore& core) {
  if (steadyNs() < core.injection.stalled_until_ns.load(std::memory_order_acquire)) return true;
  core.injection.stalled_until_ns.store(0, std::memory_order_relaxed);
  return false;
}

/// A `deadline` fault when onExecute took longer than the component's <deadline>.
void checkDeadline(Component& c, std::int64_t took_ns) {
  detail::ComponentCore& core = coreOf(c);
  if (took_ns <= core.deadline_ns) return;
  core.deadline_overruns.fetch_add(1, std::memory_order_relaxed);
  FaultEvent ev;
  ev.kind = FaultKind::Deadline;
  ev.t_ns = steadyNs();
  FaultEvent::copyInto(ev.component, core.instance_name);
  formatDetail(ev, "onExecute took {:.3f} ms (deadline {:.3f} ms)", took_ns / 1e6, core.deadline_ns / 1e6);
  reportFault(c, ev);
}

}  // namespace

Executor::Executor(ExecutorConfig config, Warn warn) : config_(std::move(config)), warn_(std::move(warn)) {}

Executor::~Executor() {
  if (thread_.joinable()) {
    requestStop();
    if (exited_.load()) thread_.join();
    else thread_.detach();  // a hung thread cannot be joined; the process is ending
  }
}

void Executor::add(Component& c) {
  members_.push_back(&c);
  coreOf(c).executor.store(this, std::memory_order_release);
}

void Executor::addInput(ExternalInput& input) {
  inputs_.push_back(&input);
  sleep_words_.reserve(inputs_.size() + 1);
}

void Executor::prepare(std::function<void()> before_park, std::function<void()> at_exit) {
  prepared_ = true;
  before_park_ = std::move(before_park);
  at_exit_ = std::move(at_exit);
  gate_.store(0, std::memory_order_relaxed);
  thread_ = std::thread([this] { threadMain(); });
}

void Executor::start(bool adopt) {
  adopt_ = adopt;
  release();
  waitStarted();
}

void Executor::release() {
  if (prepared_) {  // parked at the gate, or about to be
    gate_.store(1, std::memory_order_release);
    gate_.notify_one();
  } else if (!thread_.joinable()) {
    thread_ = std::thread([this] { threadMain(); });
  }
}

void Executor::waitStarted() const {
  while (!started_.load(std::memory_order_acquire) && !exited_.load()) std::this_thread::yield();
}

void Executor::abandon() {
  abandoned_.store(true, std::memory_order_release);
  leaveStopBarrier();  // a fresh executor cycles in its place, or none
  requestStop();
}

void Executor::leaveStopBarrier() {
  if (stop_barrier_ && !left_stop_barrier_.exchange(true, std::memory_order_acq_rel)) stop_barrier_->leave();
}

void Executor::waitStopBarrier() {
  if (stop_barrier_ == nullptr) return;
  while (!stop_barrier_->clear()) {
    runMail();  // a call from a component still in its last cycle
    const auto poll = std::chrono::steady_clock::now() + std::chrono::milliseconds(1);
    sleepUntil(&poll);
  }
}

bool StopBarrier::waitClear(std::chrono::steady_clock::time_point deadline) const {
  while (!clear()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return true;
}

void Executor::requestStop() {
  stop_.store(true, std::memory_order_release);
  signal_.notify();
  gate_.store(1, std::memory_order_release);  // a parked thread leaves
  gate_.notify_one();
}

bool Executor::join(std::chrono::nanoseconds timeout) {
  if (!thread_.joinable()) return true;
  auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!exited_.load(std::memory_order_acquire)) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  thread_.join();
  return true;
}

void Executor::post(std::function<void()> job) {
  {
    std::lock_guard lock(mail_mutex_);
    mail_.push_back(std::move(job));
  }
  has_mail_.store(true, std::memory_order_release);
  signal_.notify();
}

void Executor::runMail() {
  if (!has_mail_.exchange(false, std::memory_order_acq_rel)) return;
  std::vector<std::function<void()>> jobs;
  {
    std::lock_guard lock(mail_mutex_);
    jobs.swap(mail_);
  }
  for (auto& job : jobs) job();
}

void Executor::interrupt() {
  if (!exited_.load(std::memory_order_acquire) && started_.load(std::memory_order_acquire))
    interruptThread(native_.load());
}

void Executor::replaceMember(Component& failed, Component& alternative) {
  for (Component*& m : members_)
    if (m == &failed) m = &alternative;
  coreOf(alternative).executor.store(this, std::memory_order_release);
}

void Executor::setUpThread() {
  thread_id_.store(std::this_thread::get_id());
  native_.store(pthread_self());
  pthread_setname_np(pthread_self(), config_.name.substr(0, 15).c_str());
  prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0);  // 1 ns slack: sub-millisecond periods stay precise
  installAltStack();
  if (config_.policy == SchedPolicy::Other && config_.priority == 0) return;
  sched_param sp{};
  int policy = config_.policy == SchedPolicy::Fifo         ? SCHED_FIFO
               : config_.policy == SchedPolicy::RoundRobin ? SCHED_RR
                                                           : SCHED_OTHER;
  sp.sched_priority = policy == SCHED_OTHER ? 0 : config_.priority;
  if (int err = pthread_setschedparam(pthread_self(), policy, &sp); err != 0 && warn_) {
    warn_(
        fmt::format("executor '{}': cannot set scheduling policy {} priority {}: {} "
                    "(running with the default policy; needs CAP_SYS_NICE or an rtprio limit)",
                    config_.name,
                    policy == SCHED_FIFO ? "fifo"
                    : policy == SCHED_RR ? "rr"
                                         : "other",
                    config_.priority, std::generic_category().message(err)));
  }
}

void Executor::threadMain() {
  setUpThread();
  run();
  leaveStopBarrier();  // a parked thread asked to stop, or one that came back after it was abandoned
  // Every way out: at_exit_ first (the thread may hold what only it can release), then exited_.
  if (at_exit_) at_exit_();
  exited_.store(true, std::memory_order_release);
}

void Executor::run() {
  if (prepared_) {  // parked until start() or a stop
    // Its allocator's arena made now, not on its way to the first step: a thread's first
    // allocation maps memory for it (glibc's per-thread arenas). Volatile: not elided.
    void* volatile first = std::malloc(64);
    std::free(first);
    if (before_park_) before_park_();
    gate_.wait(0, std::memory_order_acquire);
    if (stop_.load(std::memory_order_acquire)) return;
  }
  for (Component* c : members_) {
    if (!adopt_) transition(*c, Transition::Start);
    if (!coreOf(*c).critical.empty()) takeCheckpoint(coreOf(*c), steadyNs());  // the state to return to
  }
  started_.store(true, std::memory_order_release);
  if (go_)
    while (go_->load(std::memory_order_acquire) == 0) go_->wait(0, std::memory_order_acquire);
  if (config_.kind == ExecutorKind::Periodic) runPeriodic();
  else runAperiodic();
  if (abandoned_.load(std::memory_order_acquire)) return;  // came back after all: the members are not ours
  serviceBetweenCycles();
  leaveStopBarrier();
  waitStopBarrier();  // no member stops while another component may still call it
  for (auto it = members_.rbegin(); it != members_.rend(); ++it) transition(**it, Transition::Stop);
  runMail();  // answer calls that arrived meanwhile (they fail fast: provider not active)
}

void Executor::serviceBetweenCycles() {
  runMail();
  for (Component* c : members_) {
    if (abandoned_.load(std::memory_order_acquire)) [[unlikely]]
      return;
    dispatchEvents(*c);
  }
}

bool Executor::execute(Component& c) {
  detail::ComponentCore& core = coreOf(c);
  const std::int64_t t0 = core.deadline_ns ? steadyNs() : 0;
  const bool ok = invoke(c, Callback::Execute);
  if (ok) {
    core.executions.fetch_add(1, std::memory_order_relaxed);
    // The first good step after a recovery is the `recovered` moment (docs/fault-log.md).
    if (core.fault.recovering_id.load(std::memory_order_relaxed) != 0 && core.fault_sink) [[unlikely]]
      core.fault_sink->recovered(c, steadyNs());
  }
  if (core.deadline_ns && ok) checkDeadline(c, steadyNs() - t0);  // a failed step is already a fault
  return ok;
}

void Executor::cycle() {
  // Indexed: a recovery on this thread may put a replacement in a member's place.
  for (std::size_t i = 0; i < members_.size(); ++i) {
    Component* c = members_[i];
    if (c->state() != State::Active) continue;
    detail::ComponentCore& core = coreOf(*c);
    if (core.injection.stalled_until_ns.load(std::memory_order_relaxed) != 0 && stalled(core)) continue;
    if (core.gate != nullptr && !core.gate->open()) continue;  // OPRoS's depends: a target has not run
    core.input_pending.store(false, std::memory_order_relaxed);
    const bool ok = execute(*c);
    if (core.gate != nullptr) core.gate->ran();
    if (abandoned_.load(std::memory_order_acquire)) [[unlikely]]
      return;  // back from a hang, too late
    if (ok) continue;
    // Recovered at once on this thread (reset, or a preloaded replacement): the step this
    // cycle owes is run now, once — not at the next release.
    Component* now = members_[i];
    if (now->state() == State::Active && coreOf(*now).fault.recovering_id.load(std::memory_order_relaxed) != 0)
      execute(*now);
  }
  const std::int64_t now = steadyNs();
  for (Component* c : members_) {
    if (c->state() != State::Active) continue;
    invoke(*c, Callback::Updated);
    if (abandoned_.load(std::memory_order_acquire)) [[unlikely]]
      return;
    checkpointIfDue(coreOf(*c), now);  // the cycle boundary: no callback of c is running
  }
  cycles_.fetch_add(1, std::memory_order_relaxed);
  last_cycle_ns_.store(now, std::memory_order_relaxed);
}

bool Executor::sleepUntil(const std::chrono::steady_clock::time_point* deadline) {
  // Abandoned: its inputs are the executor's that replaced it, whatever this thread does now.
  if (inputs_.empty() || abandoned_.load(std::memory_order_acquire)) {
    if (deadline) return signal_.waitUntil(*deadline);
    signal_.wait();
    return true;
  }
  if (signal_.consume()) return true;
  if (deadline && *deadline <= std::chrono::steady_clock::now()) return signal_.consume();
  sleep_words_.assign(1, FutexWaiter{});  // [0]: the signal's own word
  bool arrived = false;
  for (ExternalInput* in : inputs_) {
    std::optional<FutexWaiter> word = in->announceSleep();
    if (!word) {
      arrived = true;
      break;
    }
    sleep_words_.push_back(*word);
  }
  if (!arrived) signal_.sleepAlso(sleep_words_, deadline);
  for (std::size_t i = 1; i < sleep_words_.size(); ++i) inputs_[i - 1]->endSleep();
  if (arrived || signal_.consume()) return true;
  // Woken by an input (draining finds out), at the deadline, or for nothing: only the deadline
  // is a "no".
  return deadline == nullptr || std::chrono::steady_clock::now() < *deadline;
}

void Executor::drainInputs() {
  if (abandoned_.load(std::memory_order_acquire)) [[unlikely]]
    return;
  bool drained = false;
  for (ExternalInput* in : inputs_) drained |= in->drain();
  // Delivering woke this executor; it is awake, and what follows (events, mail, the inputs'
  // flags) looks at everything a notification could have been for.
  if (drained) signal_.consume();
}

void Executor::runPeriodic() {
  using Clock = std::chrono::steady_clock;
  const auto period = config_.period;
  auto next = Clock::now();
  while (!stop_.load(std::memory_order_acquire)) {
    drainInputs();
    cycle();
    next += period;
    auto now = Clock::now();
    if (now > next) {  // overran: count it and skip the releases already missed
      overruns_.fetch_add(1, std::memory_order_relaxed);
      auto missed = (now - next) / period + 1;
      next += missed * period;
    }
    while (!stop_.load(std::memory_order_acquire) && sleepUntil(&next)) {
      drainInputs();
      serviceBetweenCycles();
    }
    serviceBetweenCycles();
  }
}

void Executor::runAperiodic() {
  last_cycle_ns_.store(steadyNs(), std::memory_order_relaxed);
  while (!stop_.load(std::memory_order_acquire)) {
    sleepUntil(nullptr);
    drainInputs();
    serviceBetweenCycles();
    bool input = false;
    for (Component* c : members_) input |= coreOf(*c).input_pending.load(std::memory_order_acquire);
    if (input && !stop_.load(std::memory_order_acquire)) cycle();
  }
}

}  // namespace keel::runtime
