#include "runtime/executor.hpp"

#include <gtest/gtest.h>
#include <sched.h>

#include <array>
#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

#include "keel/component.hpp"
#include "runtime/guard.hpp"
#include "runtime/invoke.hpp"
#include "support/crash.hpp"
#include "support/recording_hooks.hpp"

namespace keel::runtime {
namespace {

using namespace std::chrono_literals;
using test::eventually;

/// Records the order of its callbacks into a shared trace, and the threads they ran on.
class Tracer : public Component {
 public:
  Tracer(std::vector<std::string>* trace, std::mutex* m) : trace_(trace), mutex_(m) {}
  ReturnCode onStart() override { return note("start"); }
  ReturnCode onStop() override { return note("stop"); }
  ReturnCode onExecute() override {
    executions.fetch_add(1);
    return note("execute");
  }
  ReturnCode onUpdated() override { return note("updated"); }
  std::atomic<int> executions{0};
  std::atomic<std::thread::id> last_thread{};

 private:
  ReturnCode note(const char* what) {
    last_thread = std::this_thread::get_id();
    std::lock_guard lock(*mutex_);
    // The first 63 callbacks, and the latest in the last slot, however late the test stops it.
    if (trace_->size() < 64) trace_->push_back(instanceName() + "." + what);
    else trace_->back() = instanceName() + "." + what;
    return ReturnCode::Ok;
  }
  std::vector<std::string>* trace_;
  std::mutex* mutex_;
};

class ExecutorTest : public ::testing::Test {
 protected:
  void SetUp() override { installSignalHandlers(); }
  template <class C>
  void ready(C& c, const std::string& name) {
    test::manage(c, name, hooks_);
    ASSERT_TRUE(transition(c, Transition::Initialize));
  }
  test::RecordingHooks hooks_;
  std::vector<std::string> trace_;
  std::mutex trace_mutex_;
};

TEST_F(ExecutorTest, ATaskRunsItsMembersInDeclaredOrderExecuteThenUpdated) {
  Tracer a(&trace_, &trace_mutex_), b(&trace_, &trace_mutex_);
  ready(a, "a");
  ready(b, "b");
  Executor ex({"task", ExecutorKind::Periodic, 2ms, 0, SchedPolicy::Other});
  ex.add(a);
  ex.add(b);
  ex.start();
  ASSERT_TRUE(eventually([&] { return b.executions.load() >= 2; }));
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  std::lock_guard lock(trace_mutex_);
  ASSERT_GE(trace_.size(), 6u);
  EXPECT_EQ(std::vector<std::string>(trace_.begin(), trace_.begin() + 6),
            (std::vector<std::string>{"a.start", "b.start", "a.execute", "b.execute", "a.updated", "b.updated"}));
  EXPECT_EQ(trace_.back(), "a.stop");  // stopped in reverse order
  EXPECT_EQ(a.state(), State::Inactive);
  EXPECT_EQ(b.state(), State::Inactive);
}

TEST_F(ExecutorTest, APreparedThreadWaitsWithItsMembersUnstartedUntilStartThenRunsOnThatThread) {
  Tracer a(&trace_, &trace_mutex_);
  ready(a, "a");
  Executor ex({"standby", ExecutorKind::Periodic, 1ms, 0, SchedPolicy::Other});
  ex.add(a);
  ex.prepare();
  std::this_thread::sleep_for(50ms);  // 50 periods: a thread that ran would have started and stepped
  {
    std::lock_guard lock(trace_mutex_);
    EXPECT_TRUE(trace_.empty());
  }
  EXPECT_EQ(a.state(), State::Ready);
  ex.start();
  ASSERT_TRUE(eventually([&] { return a.executions.load() >= 2; }));
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  std::lock_guard lock(trace_mutex_);
  ASSERT_GE(trace_.size(), 3u);
  EXPECT_EQ(trace_.front(), "a.start");
  EXPECT_EQ(trace_.back(), "a.stop");
}

TEST_F(ExecutorTest, APreparedThreadAskedToStopLeavesWithoutStartingOrStoppingItsMembers) {
  Tracer a(&trace_, &trace_mutex_);
  ready(a, "a");
  Executor ex({"standby", ExecutorKind::Periodic, 1ms, 0, SchedPolicy::Other});
  ex.add(a);
  ex.prepare();
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  std::lock_guard lock(trace_mutex_);
  EXPECT_TRUE(trace_.empty());
  EXPECT_EQ(a.state(), State::Ready);
  EXPECT_EQ(a.executions.load(), 0);
}

TEST_F(ExecutorTest, APreparedThreadRunsItsBeforeParkHookAndGoesOnAtOnceWhenTheHookReleasesIt) {
  // A standby host's takeover: the thread that wakes to the death releases itself and runs its
  // members, with no start() from another thread.
  Tracer a(&trace_, &trace_mutex_);
  ready(a, "a");
  Executor ex({"standby", ExecutorKind::Periodic, 1ms, 0, SchedPolicy::Other});
  ex.add(a);
  std::atomic<std::thread::id> hook_thread{};
  std::atomic<bool> go{false};
  ex.prepare([&] {
    hook_thread = std::this_thread::get_id();
    while (!go.load()) std::this_thread::sleep_for(1ms);  // the role lock a standby sleeps on
    ex.release();
  });
  std::this_thread::sleep_for(20ms);
  EXPECT_EQ(a.state(), State::Ready);  // not started while the hook waits
  go = true;
  ASSERT_TRUE(eventually([&] { return a.executions.load() >= 2; }));
  EXPECT_EQ(a.last_thread.load(), hook_thread.load());  // the hook's thread runs the members
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  EXPECT_EQ(a.state(), State::Inactive);
}

TEST_F(ExecutorTest, TheAtExitHookRunsOnTheThreadHoweverItEnds) {
  // What the thread holds (a standby's role lock) can only be released by that thread.
  Tracer a(&trace_, &trace_mutex_);
  ready(a, "a");
  auto runs = [&](auto&& end) {
    Executor ex({"task", ExecutorKind::Periodic, 1ms, 0, SchedPolicy::Other});
    ex.add(a);
    std::atomic<std::thread::id> ran_on{}, exited_on{};
    ex.prepare([&] { ran_on = std::this_thread::get_id(); }, [&] { exited_on = std::this_thread::get_id(); });
    end(ex);
    EXPECT_TRUE(ex.join(5s));
    return exited_on.load() != std::thread::id{} && exited_on.load() == ran_on.load();
  };
  EXPECT_TRUE(runs([](Executor& ex) { ex.requestStop(); }));  // parked, never started
  EXPECT_TRUE(runs([&](Executor& ex) {                        // started, stopped
    ex.start();
    ASSERT_TRUE(eventually([&] { return a.executions.load() >= 1; }));
    ex.requestStop();
  }));
  EXPECT_TRUE(runs([&](Executor& ex) {  // started, then abandoned
    ex.start(/*adopt=*/true);
    ex.abandon();
  }));
}

TEST_F(ExecutorTest, PeriodicExecutorKeepsItsRateOverTime) {
  Tracer a(&trace_, &trace_mutex_);
  ready(a, "a");
  Executor ex({"p", ExecutorKind::Periodic, 5ms, 0, SchedPolicy::Other});
  ex.add(a);
  const auto t0 = std::chrono::steady_clock::now();
  ex.start();
  std::this_thread::sleep_for(500ms);
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  const auto releases = (std::chrono::steady_clock::now() - t0) / 5ms + 1;  // however late the stop
  // Absolute-time sleeps do not drift, and missed releases are skipped, not caught up: never
  // more steps than releases. Generous below: a busy CI machine.
  EXPECT_GE(a.executions.load(), 50);
  EXPECT_LE(a.executions.load(), releases + 1);
}

TEST_F(ExecutorTest, AllCallbacksOfAMemberRunOnTheExecutorThread) {
  Tracer a(&trace_, &trace_mutex_);
  ready(a, "a");
  Executor ex({"p", ExecutorKind::Periodic, 1ms, 0, SchedPolicy::Other});
  ex.add(a);
  ex.start();
  ASSERT_TRUE(eventually([&] { return a.executions.load() > 0; }));
  EXPECT_NE(a.last_thread.load(), std::this_thread::get_id());
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  EXPECT_NE(a.last_thread.load(), std::this_thread::get_id());  // onStop too
}

class Consumer : public Component {
 public:
  InputDataPort<int> in{this, "in"};
  InputEventPort<Event> events{this, "events"};
  ReturnCode onExecute() override {
    while (auto v = in.pop()) sum += *v;
    exec_thread = std::this_thread::get_id();
    executions.fetch_add(1);
    return ReturnCode::Ok;
  }
  ReturnCode onEvent(InputEventPortBase& port) override {
    if (&port == &events) {
      event_names.push_back(events.current().name);
      event_thread = std::this_thread::get_id();
      event_count.fetch_add(1);
    }
    return ReturnCode::Ok;
  }
  std::atomic<int> sum{0};
  std::atomic<int> executions{0};
  std::atomic<int> event_count{0};
  std::vector<std::string> event_names;
  std::atomic<std::thread::id> event_thread{};
  std::atomic<std::thread::id> exec_thread{};
};

class Producer : public Component {
 public:
  OutputDataPort<int> out{this, "out"};
  OutputEventPort<Event> events{this, "events"};
};

TEST_F(ExecutorTest, AperiodicExecutorRunsOnlyWhenInputArrives) {
  Consumer c;
  Producer p;
  ready(c, "c");
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep;
  test::wire(p.out, c.in, keep);
  Executor ex({"aperiodic", ExecutorKind::Aperiodic, 0ms, 0, SchedPolicy::Other});
  ex.add(c);
  ex.start();
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(c.executions.load(), 0) << "ran without input: spinning";
  p.out.push(5);
  ASSERT_TRUE(eventually([&] { return c.sum.load() == 5; }));
  p.out.push(7);
  ASSERT_TRUE(eventually([&] { return c.sum.load() == 12; }));
  std::this_thread::sleep_for(50ms);
  EXPECT_LE(c.executions.load(), 2);
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
}

/// Values from "another process": a count bumped by the test, its futex word woken as a ring's
/// writer wakes its readers. Draining pushes each new value through a real connection.
class CountingInput : public ExternalInput {
 public:
  explicit CountingInput(OutputDataPort<int>& out) : out_(out) {}
  void send(int value) {
    value_.store(value);
    sent_.fetch_add(1);
    word_.fetch_add(1);
    if (sleeping_.load() != 0) futexWakeAll(word_, FutexScope::Shared);
  }
  std::optional<FutexWaiter> announceSleep() override {
    const std::uint32_t w = word_.load();
    sleeping_.fetch_add(1);
    if (sent_.load() != drained_) {
      sleeping_.fetch_sub(1);
      return std::nullopt;
    }
    return FutexWaiter{&word_, w, FutexScope::Shared};
  }
  void endSleep() override { sleeping_.fetch_sub(1); }
  bool drain() override {
    drain_thread = std::this_thread::get_id();
    const int sent = sent_.load();
    if (sent == drained_) return false;
    drained_ = sent;
    out_.push(value_.load());
    drains.fetch_add(1);
    return true;
  }
  std::atomic<std::thread::id> drain_thread{};
  std::atomic<int> drains{0};  // drains that found a value

 private:
  OutputDataPort<int>& out_;
  std::atomic<int> value_{0};
  std::atomic<int> sent_{0};
  int drained_ = 0;
  std::atomic<std::uint32_t> word_{0};
  std::atomic<std::uint32_t> sleeping_{0};
};

TEST_F(ExecutorTest, AnExecutorSleepsOnItsExternalInputsAndDrainsThemOnItsThreadBeforeTheStep) {
  ASSERT_TRUE(futexWaitAnySupported()) << "this kernel has no futex_waitv (Linux 5.16)";
  for (ExecutorKind kind : {ExecutorKind::Aperiodic, ExecutorKind::Periodic}) {
    SCOPED_TRACE(kind == ExecutorKind::Aperiodic ? "aperiodic" : "periodic (1 h: only an input wakes it)");
    Consumer c;
    Producer p;  // the in-process end the input delivers through; nobody else pushes on it
    ready(c, "c");
    std::vector<std::unique_ptr<detail::ConnectionBase>> keep;
    test::wire(p.out, c.in, keep);
    CountingInput input(p.out);
    Executor ex({"external", kind, 1h, 0, SchedPolicy::Other});
    ex.add(c);
    ex.addInput(input);
    ex.start();
    // A periodic task runs its first cycle at its start, after start() has returned: wait for
    // it, or a late first cycle reads as a step without input.
    if (kind == ExecutorKind::Periodic) {
      ASSERT_TRUE(eventually([&] { return c.executions.load() == 1; }));
    }
    const int first_steps = c.executions.load();
    std::this_thread::sleep_for(50ms);
    EXPECT_EQ(c.executions.load(), first_steps) << "ran without input: spinning";
    input.send(5);
    ASSERT_TRUE(eventually([&] { return input.drains.load() == 1; })) << "the input's wake did not reach the executor";
    EXPECT_EQ(input.drain_thread.load(), c.exec_thread.load()) << "drained off the component's thread";
    if (kind == ExecutorKind::Aperiodic) {  // the value wakes the step; a periodic task's waits for its period
      ASSERT_TRUE(eventually([&] { return c.sum.load() == 5; }));
      input.send(7);
      ASSERT_TRUE(eventually([&] { return c.sum.load() == 12; }));
    }
    ex.requestStop();
    ASSERT_TRUE(ex.join(5s));
  }
}

TEST_F(ExecutorTest, EventsAreDeliveredToOnEventOnTheReceiversExecutorInOrder) {
  Consumer c;
  Producer p;
  ready(c, "c");
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep;
  test::wire(p.events, c.events, keep);
  Executor ex({"slow", ExecutorKind::Periodic, 1h, 0, SchedPolicy::Other});
  ex.add(c);
  ex.start();
  for (const char* n : {"one", "two", "three"}) p.events.send(Event{n, 0, 0});
  // Delivered as they arrive, not at the next release, an hour away.
  ASSERT_TRUE(eventually([&] { return c.event_count.load() == 3; }));
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  EXPECT_EQ(c.event_names, (std::vector<std::string>{"one", "two", "three"}));
  EXPECT_NE(c.event_thread.load(), std::this_thread::get_id());
}

class Crasher : public Component {
 public:
  ReturnCode onExecute() override {
    if (++n == 3) test::segfault();
    return ReturnCode::Ok;
  }
  int n = 0;
};

TEST_F(ExecutorTest, AFaultingMemberGoesToErrorAndTheOthersKeepRunning) {
  Crasher bad;
  Tracer good(&trace_, &trace_mutex_);
  ready(bad, "bad");
  ready(good, "good");
  Executor ex({"task", ExecutorKind::Periodic, 1ms, 0, SchedPolicy::Other});
  ex.add(bad);
  ex.add(good);
  ex.start();
  ASSERT_TRUE(eventually([&] { return bad.state() == State::Error; }));
  int before = good.executions.load();
  ASSERT_TRUE(eventually([&] { return good.executions.load() > before + 20; }));
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  EXPECT_EQ(bad.n, 3) << "a component in Error must not be executed";
  auto faults = hooks_.faults();
  ASSERT_EQ(faults.size(), 1u);
  EXPECT_EQ(faults[0].kind, FaultKind::Signal);
  EXPECT_EQ(std::string(faults[0].componentName()), "bad");
}

// One cycle that overruns by several periods is one overrun, and the releases it missed are
// skipped, not run back to back to catch up: the next cycles keep the period.
TEST_F(ExecutorTest, AnOverrunIsCountedOnceAndTheMissedReleasesAreSkipped) {
  constexpr auto kPeriod = 50ms;
  class Slow : public Component {
   public:
    ReturnCode onExecute() override {
      starts[n] = std::chrono::steady_clock::now();
      if (++n == 2) std::this_thread::sleep_for(175ms);  // 3.5 periods: three releases missed
      return ReturnCode::Ok;
    }
    std::atomic<int> n{0};
    std::array<std::chrono::steady_clock::time_point, 64> starts{};
  } slow;
  ready(slow, "slow");
  Executor ex({"p", ExecutorKind::Periodic, kPeriod, 0, SchedPolicy::Other});
  ex.add(slow);
  ex.start();
  ASSERT_TRUE(eventually([&] { return slow.n.load() >= 5; }));
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  EXPECT_EQ(ex.stats().overruns, 1u) << "the slow cycle once, not once per missed release";
  // Caught up, cycles 3 and 4 would start back to back; skipped, a period apart (generous: a
  // busy machine may wake late, never early).
  EXPECT_GE(slow.starts[3] - slow.starts[2], kPeriod / 2);
  EXPECT_GE(slow.starts[4] - slow.starts[3], kPeriod / 2);
}

TEST_F(ExecutorTest, CountsDeadlineOverrunsOfAMember) {
  class Sometimes : public Component {
   public:
    ReturnCode onExecute() override {
      if (++n % 4 == 0) std::this_thread::sleep_for(20ms);
      return ReturnCode::Ok;
    }
    std::atomic<int> n{0};
  } c;
  ready(c, "c");
  coreOf(c).deadline_ns = 10'000'000;  // <deadline>10</deadline>
  Executor ex({"p", ExecutorKind::Periodic, 1ms, 0, SchedPolicy::Other});
  ex.add(c);
  ex.start();
  ASSERT_TRUE(eventually([&] { return c.n.load() >= 12; }));
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  const auto overruns = coreOf(c).deadline_overruns.load();
  EXPECT_GE(overruns, 3u);
  EXPECT_LE(overruns, static_cast<std::uint64_t>(c.n.load() / 4 + 1)) << "fast cycles counted as overruns";
}

TEST_F(ExecutorTest, RunsSubMillisecondPeriods) {
  class Stamper : public Component {
   public:
    ReturnCode onExecute() override {
      if (count < stamps.size()) stamps[count++] = std::chrono::steady_clock::now();
      return ReturnCode::Ok;
    }
    std::vector<std::chrono::steady_clock::time_point> stamps = std::vector<std::chrono::steady_clock::time_point>(400);
    std::size_t count = 0;
  } c;
  ready(c, "c");
  Executor ex({"fast", ExecutorKind::Periodic, 500us, 0, SchedPolicy::Other});
  ex.add(c);
  ex.start();
  std::this_thread::sleep_for(300ms);
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  // With a millisecond granularity no two releases would be closer than ~1 ms. On a loaded
  // machine some releases are late, but many consecutive ones are still ~0.5 ms apart.
  int short_gaps = 0;
  for (std::size_t i = 1; i < c.count; ++i) short_gaps += (c.stamps[i] - c.stamps[i - 1]) < 800us;
  EXPECT_GE(short_gaps, 20) << "of " << c.count << " executions";
}

TEST_F(ExecutorTest, AppliesTheSchedulingPolicyOrWarnsWhenTheOsRefusesIt) {
  class PolicyProbe : public Component {
   public:
    ReturnCode onExecute() override {
      policy.store(sched_getscheduler(0));
      runs.fetch_add(1);
      return ReturnCode::Ok;
    }
    std::atomic<int> policy{-1};
    std::atomic<int> runs{0};
  } probe;
  ready(probe, "probe");
  std::vector<std::string> warnings;
  std::mutex wm;
  Executor ex({"rt", ExecutorKind::Periodic, 1ms, 10, SchedPolicy::Fifo}, [&](const std::string& w) {
    std::lock_guard lock(wm);
    warnings.push_back(w);
  });
  ex.add(probe);
  ex.start();
  ASSERT_TRUE(eventually([&] { return probe.runs.load() > 3; })) << "a refused policy stopped the executor";
  ex.requestStop();
  ASSERT_TRUE(ex.join(5s));
  std::lock_guard lock(wm);
  if (warnings.empty()) {
    EXPECT_EQ(probe.policy.load(), SCHED_FIFO) << "no warning, so the thread must run SCHED_FIFO";
  } else {
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0].rfind("executor 'rt': cannot set scheduling policy fifo priority 10: ", 0), 0u)
        << warnings[0];
    EXPECT_EQ(probe.policy.load(), SCHED_OTHER);
  }
}

}  // namespace
}  // namespace keel::runtime
