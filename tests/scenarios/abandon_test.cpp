// Hung callbacks that cannot be interrupted (docs/fault-handling.md "Hung components"): a
// component hangs with keel's interrupt signal blocked, so the signal sent to its thread cannot
// end the callback. The fault manager then abandons that executor: a new one takes its other
// members (they keep executing) and, when there is one, the alternative in the hung one's place.
#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <thread>

#include "engine/engine.hpp"
#include "log/schema.hpp"
#include "runtime/component_core.hpp"
#include "runtime/guard.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/recording_hooks.hpp"

namespace keel {
namespace {

namespace schema = log::schema;
namespace ev = schema::event;
namespace fd = schema::field;
using namespace std::chrono_literals;

std::atomic<bool> g_hang{false};     // the next onExecute of Stubborn hangs
std::atomic<bool> g_release{false};  // ends the hang (at the end of a test)
std::atomic<int> g_last{0};          // the last value Ticker received

class Stubborn : public Component {
 public:
  OutputDataPort<int> out{this, "out"};
  ReturnCode onExecute() override {
    out.push(++n_);
    if (g_hang.exchange(false)) {
      sigset_t block, old;
      sigemptyset(&block);
      sigaddset(&block, runtime::interruptSignal());
      pthread_sigmask(SIG_BLOCK, &block, &old);  // what a badly behaved library might do
      while (!g_release.load()) std::this_thread::sleep_for(1ms);
      pthread_sigmask(SIG_SETMASK, &old, nullptr);
    }
    return ReturnCode::Ok;
  }

 private:
  int n_ = 0;
};

class StubbornBackup : public Component {
 public:
  OutputDataPort<int> out{this, "out"};
  ReturnCode onExecute() override {
    out.push(1000 + ++n_);
    return ReturnCode::Ok;
  }

 private:
  int n_ = 0;
};

class Ticker : public Component {
 public:
  InputDataPort<int> in{this, "in"};
  ReturnCode onExecute() override {
    if (auto v = in.pop()) g_last.store(*v);
    return ReturnCode::Ok;
  }
};

KEEL_REGISTER_COMPONENT(Stubborn)
KEEL_REGISTER_COMPONENT(StubbornBackup)
KEEL_REGISTER_COMPONENT(Ticker)

class Abandon : public ::testing::Test {
 protected:
  void SetUp() override {
    g_hang = false;
    g_release = false;
    g_last = 0;
  }
  void TearDown() override { g_release = true; }

  std::unique_ptr<engine::Engine> start(const std::string& package) {
    auto set = profile::load(std::string(KEEL_SCENARIOS) + "/abandon/" + package);
    EXPECT_TRUE(set);
    engine::EngineOptions eo;
    eo.log_path = log_;
    eo.search_path = {};
    eo.warn = [](const std::string&) {};
    auto engine = engine::Engine::create(std::move(*set), eo);
    EXPECT_TRUE(engine) << (engine ? "" : engine.error().message);
    if (!engine) return nullptr;
    EXPECT_TRUE((*engine)->start());
    return std::move(*engine);
  }

  /// Hangs stubborn and waits until the fault manager has handled the hang (generously).
  void hangAndWait(engine::Engine& engine) {
    std::this_thread::sleep_for(60ms);
    g_hang = true;
    const auto until = std::chrono::steady_clock::now() + 5s;
    while (std::chrono::steady_clock::now() < until) {
      for (const auto& h : engine.faultManager().handlings())
        if (h.component == "stubborn" && h.actions.find("escalate") != std::string::npos &&
            (h.actions.find("replace") != std::string::npos || h.actions.find("stop") != std::string::npos))
          return;
      std::this_thread::sleep_for(5ms);
    }
    ADD_FAILURE() << "the hang was not handled";
  }

  static std::uint64_t executions(engine::Engine& engine, const char* name) {
    return runtime::coreOf(*engine.find(name)).executions.load();
  }

  static bool hasExecutor(engine::Engine& engine, const std::string& name) {
    for (const auto* ex : engine.executors())
      if (ex->config().name == name) return true;
    return false;
  }

  // one file per test and process: ctest runs the tests of this binary in parallel
  std::string log_ = ::testing::TempDir() + "abandon_" +
                     ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                     std::to_string(::getpid()) + ".jsonl";
};

TEST_F(Abandon, AnUninterruptibleHangAbandonsItsExecutorAndTheOthersMoveToANewOne) {
  auto engine = start("stop.xml");
  ASSERT_TRUE(engine);
  hangAndWait(*engine);
  const auto ticks = executions(*engine, "ticker");
  EXPECT_TRUE(test::eventually([&] { return executions(*engine, "ticker") > ticks + 10; }))
      << "the ticker runs on (5 ms period)";
  EXPECT_TRUE(hasExecutor(*engine, "shared+"));
  EXPECT_EQ(engine->find("stubborn")->state(), State::Error);
  EXPECT_EQ(engine->find("ticker")->state(), State::Active);
  g_release = true;
  engine->shutdown();

  const auto log = test::readLog(log_);
  bool escalated = false, stopped = false;
  for (const auto& a : test::eventsOf(log, ev::kAction)) {
    if (a[fd::kComponent] != "stubborn") continue;
    const std::string detail = a.value(fd::kDetail, "");
    if (a[fd::kAction] == "escalate" && detail.find("did not return when interrupted") != std::string::npos)
      escalated = true;
    if (a[fd::kAction] == "stop" && a[fd::kOutcome] == schema::kOk && detail.find("shared+") != std::string::npos)
      stopped = true;
  }
  EXPECT_TRUE(escalated);
  EXPECT_TRUE(stopped);
  auto detected = test::eventsOf(log, ev::kDetected);
  ASSERT_FALSE(detected.empty());
  EXPECT_EQ(detected[0][fd::kKind], "heartbeat");
}

TEST_F(Abandon, TheAlternativeOfAnUninterruptibleHangTakesItsPlaceOnTheNewExecutor) {
  auto engine = start("replace.xml");
  ASSERT_TRUE(engine);
  hangAndWait(*engine);
  ASSERT_TRUE(test::eventually([&] {
    const Component* c = engine->find("stubborn");
    return c && runtime::coreOf(*c).executions.load() > 5u && g_last.load() > 1000;
  })) << "the alternative runs, and the ticker receives its values";
  Component* now = engine->find("stubborn");
  ASSERT_NE(now, nullptr);
  EXPECT_EQ(runtime::coreOf(*now).class_name, "StubbornBackup");
  EXPECT_EQ(now->state(), State::Active);
  EXPECT_TRUE(hasExecutor(*engine, "shared+"));
  g_release = true;
  engine->shutdown();

  bool replaced = false, recovered = false;
  const auto log = test::readLog(log_);
  for (const auto& a : test::eventsOf(log, ev::kAction))
    if (a[fd::kAction] == "replace" && a[fd::kOutcome] == schema::kOk)
      replaced = a[fd::kReplacement] == "StubbornBackup";
  for (const auto& r : test::eventsOf(log, ev::kRecovered)) recovered |= r[fd::kComponent] == "stubborn";
  EXPECT_TRUE(replaced);
  EXPECT_TRUE(recovered);
}

}  // namespace
}  // namespace keel
