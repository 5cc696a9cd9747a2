// The engine end to end: profiles → libraries → instances → connections → executors → stop,
// with the real test component library (found through KEEL_COMPONENT_PATH).
#include "engine/engine.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <thread>
#include <vector>

#include "runtime/component_core.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/recording_hooks.hpp"

namespace keel::engine {
namespace {

using namespace std::chrono_literals;

std::string profilePath(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/" + name; }

class EngineTest : public ::testing::Test {
 protected:
  std::unique_ptr<Engine> create(const std::string& profile) {
    auto set = profile::load(profilePath(profile));
    EXPECT_TRUE(set) << (set ? "" : set.error().front().str());
    if (!set) return nullptr;
    EngineOptions eo;
    eo.log_path = log_path_;
    eo.search_path = {KEEL_TEST_COMPONENTS, KEEL_STOCK_COMPONENTS};
    eo.warn = [](const std::string&) {};
    auto engine = Engine::create(std::move(*set), eo);
    EXPECT_TRUE(engine) << (engine ? "" : engine.error().message);
    return engine ? std::move(*engine) : nullptr;
  }
  std::string log_path_ =
      (std::filesystem::temp_directory_path() / ("keel_engine_test_" + std::to_string(::getpid()) + ".jsonl")).string();
  void TearDown() override { std::filesystem::remove(log_path_); }
};

// OPRoS's execution order: a component that depends on another executes only after it has, at
// most once per its executions; one that depends on a passive component never executes.
TEST_F(EngineTest, DependsGatesEachExecutionOnTheTargetsAsOPRoSDoes) {
  auto engine = create("execution_order.xml");
  ASSERT_TRUE(engine);
  ASSERT_TRUE(engine->start());
  auto executions = [&](const char* name) { return runtime::coreOf(*engine->find(name)).executions.load(); };
  ASSERT_TRUE(test::eventually([&] { return executions("slow") >= 6 && executions("gated") >= 3; }));
  const auto gated = executions("gated");  // first: slow only grows meanwhile
  const auto slow = executions("slow"), free = executions("free"), stuck = executions("stuck");
  engine->shutdown();
  EXPECT_LE(gated, slow) << "each execution of gated consumed one of slow's at least";
  EXPECT_GT(free, 2 * slow) << "without the order it runs at its own period (5 ms against 50 ms)";
  EXPECT_EQ(stuck, 0u) << "its target is passive and never executes";
}

TEST_F(EngineTest, RunsAPackageThroughTheWholeLifecycleInOrder) {
  auto engine = create("pipeline.xml");
  ASSERT_TRUE(engine);
  ASSERT_TRUE(engine->start());
  Component* summer = engine->find("summer");
  ASSERT_NE(summer, nullptr);
  ASSERT_TRUE(test::eventually([&] { return runtime::coreOf(*summer).executions.load() > 20; }));
  engine->shutdown();
  auto log = test::readLog(log_path_);
  for (const char* c : {"counter", "summer", "events", "doubler", "caller"}) {
    EXPECT_EQ(test::statesOf(log, c), (std::vector<std::string>{"Ready", "Active", "Inactive", "Destroyed"})) << c;
  }
  // The only faults of this package are the event logger's own (it raises one per milestone
  // from 30 values on, as many as a slow machine lets it see): nothing else faulted.
  for (const auto& d : test::eventsOf(log, "detected")) {
    EXPECT_EQ(d["component"], "events") << d.dump();
    EXPECT_EQ(d["kind"], "user") << d.dump();
  }
}

TEST_F(EngineTest, AppliesTypedPropertiesWithSubcomponentOverrides) {
  auto engine = create("pipeline.xml");
  ASSERT_TRUE(engine);
  Component* counter = engine->find("counter");
  Component* summer = engine->find("summer");
  EXPECT_EQ(counter->property<int>("step"), 2);      // overridden
  EXPECT_EQ(summer->property<double>("gain"), 0.5);  // overridden
  EXPECT_EQ(summer->property<std::string>("label"), "half");
  EXPECT_THROW(summer->property<int>("label"), PropertyError);
  EXPECT_THROW(summer->property<int>("missing"), PropertyError);
}

/// Sends `values` into `component`'s input port `port` of type T as a connection would, then
/// returns what the port hands its component, in order.
template <class T>
std::vector<T> throughQueue(Engine& engine, const std::string& component, const std::string& port,
                            const std::vector<T>& values) {
  auto* in = static_cast<detail::InputPortBase*>(runtime::coreOf(*engine.find(component)).findPort(port));
  auto connection = in->makeConnection();
  for (const T& v : values) static_cast<detail::Connection<T>*>(connection.get())->send(v);
  std::vector<T> out;
  while (auto v = static_cast<InputDataPort<T>*>(in)->pop()) out.push_back(*v);
  return out;
}

TEST_F(EngineTest, ConfiguresInputQueuesPolicyAndSizeFromTheProfile) {
  auto engine = create("queues.xml");
  ASSERT_TRUE(engine);
  auto* in = static_cast<detail::InputPortBase*>(runtime::coreOf(*engine->find("summer")).findPort("in"));
  EXPECT_EQ(in->capacity(), 64u);  // Summer.xml: FIFO, queue_size 64: full, the oldest is dropped
  std::vector<int> sent(70);
  for (int i = 0; i < 70; ++i) sent[i] = i;
  const auto fifo = throughQueue<int>(*engine, "summer", "in", sent);
  ASSERT_EQ(fifo.size(), 64u);
  EXPECT_EQ(fifo.front(), 6);
  EXPECT_EQ(fifo.back(), 69);
  // MedianVoter.xml: LAST, only the newest value counts; Brake.xml: LAST, whatever the size.
  EXPECT_EQ(throughQueue<double>(*engine, "voter", "in0", {1.0, 2.0, 3.0}), std::vector<double>{3.0});
  EXPECT_EQ(static_cast<detail::InputPortBase*>(runtime::coreOf(*engine->find("brake")).findPort("in"))->capacity(),
            1u);
}

TEST_F(EngineTest, ServiceCallsEventsAndDataFlowBetweenComponents) {
  auto engine = create("pipeline.xml");
  ASSERT_TRUE(engine);
  ASSERT_TRUE(engine->start());
  // The event logger raises a user fault once summer's milestone event reports 30 values:
  // data (counter, caller→doubler service) reached summer, and its events reached the logger.
  ASSERT_TRUE(test::eventually([&] { return runtime::coreOf(*engine->find("events")).faults.load() > 0; }));
  EXPECT_EQ(runtime::coreOf(*engine->find("caller")).faults.load(), 0u) << "the caller's service calls failed";
  EXPECT_EQ(engine->find("caller")->state(), State::Active);
  engine->shutdown();
  auto detected = test::eventsOf(test::readLog(log_path_), "detected");
  ASSERT_FALSE(detected.empty());
  EXPECT_EQ(detected[0]["kind"], "user");
  EXPECT_EQ(detected[0]["component"], "events");
  EXPECT_EQ(detected[0]["detail"], "milestone 30 reached: half");
}

TEST_F(EngineTest, AFaultyComponentGoesToErrorWhileTheRestKeepsRunning) {
  auto engine = create("crash.xml");
  ASSERT_TRUE(engine);
  ASSERT_TRUE(engine->start());
  Component* crasher = engine->find("crasher");
  Component* thrower = engine->find("thrower");
  Component* counter = engine->find("counter");
  ASSERT_TRUE(test::eventually([&] { return crasher->state() == State::Error && thrower->state() == State::Error; }));
  auto before = runtime::coreOf(*counter).executions.load();
  ASSERT_TRUE(test::eventually([&] { return runtime::coreOf(*counter).executions.load() > before + 10; }));
  EXPECT_EQ(counter->state(), State::Active);
  engine->shutdown();
  auto log = test::readLog(log_path_);
  auto detected = test::eventsOf(log, "detected");
  ASSERT_EQ(detected.size(), 2u);
  for (const auto& d : detected) {
    if (d["component"] == "crasher") {
      EXPECT_EQ(d["kind"], "signal");
      EXPECT_NE(d["detail"].get<std::string>().find("SIGSEGV in onExecute"), std::string::npos);
    } else {
      EXPECT_EQ(d["component"], "thrower");
      EXPECT_EQ(d["kind"], "exception");
      EXPECT_EQ(d["detail"], "exception in onExecute: crasher gave up");
    }
  }
  EXPECT_EQ(test::statesOf(log, "crasher"), (std::vector<std::string>{"Ready", "Active", "Error", "Destroyed"}));
}

TEST_F(EngineTest, FlattensCompositesAndConnectsThroughExportedPorts) {
  auto engine = create("with_composite.xml");
  ASSERT_TRUE(engine);
  EXPECT_NE(engine->find("pair.counter"), nullptr);
  EXPECT_NE(engine->find("pair.summer"), nullptr);
  ASSERT_TRUE(engine->start());
  ASSERT_TRUE(test::eventually([&] { return runtime::coreOf(*engine->find("events")).faults.load() > 0; }));
  engine->shutdown();
}

TEST_F(EngineTest, RejectsAPortWhoseTypeDiffersBetweenProfileAndCode) {
  auto set = profile::load(profilePath("wrong_type.xml"));
  ASSERT_TRUE(set);
  EngineOptions eo;
  eo.search_path = {KEEL_TEST_COMPONENTS};
  auto engine = Engine::create(std::move(*set), eo);
  ASSERT_FALSE(engine);
  EXPECT_EQ(engine.error().message,
            profilePath("CounterDouble.xml") +
                ":9: component 'counter': port 'count' carries 'double' in the profile but 'int' in "
                "class 'Counter'");
}

TEST_F(EngineTest, NamesTheLibraryItCannotFind) {
  auto set = profile::load(profilePath("pipeline.xml"));
  ASSERT_TRUE(set);
  EngineOptions eo;
  eo.search_path = {"/nonexistent/keel"};
  auto engine = Engine::create(std::move(*set), eo);
  ASSERT_FALSE(engine);
  EXPECT_NE(engine.error().message.find("library 'keel_test_components' not found; tried:"), std::string::npos);
  EXPECT_NE(engine.error().message.find("/nonexistent/keel/libkeel_test_components.so"), std::string::npos);
}

TEST_F(EngineTest, NamesEachFileItTriedOnceHoweverOftenItsDirectoryIsNamed) {
  auto set = profile::load(profilePath("pipeline.xml"));
  ASSERT_TRUE(set);
  EngineOptions eo;
  // KEEL_COMPONENT_PATH naming keel's own directory, or the profiles' one, again.
  eo.search_path = {"/nonexistent/keel", "/nonexistent/keel/", "/nonexistent/other/../keel", KEEL_TEST_PROFILES};
  auto engine = Engine::create(std::move(*set), eo);
  ASSERT_FALSE(engine);
  // The first component's message (each component that needs the library has one).
  const std::string& all = engine.error().message;
  const std::string m = all.substr(0, all.find(" not found; tried:", all.find(" not found; tried:") + 1));
  for (const std::string& file : {std::string("/nonexistent/keel/libkeel_test_components.so"),
                                  std::string(KEEL_TEST_PROFILES) + "/libkeel_test_components.so"}) {
    const auto first = m.find(file + "\n");
    ASSERT_NE(first, std::string::npos) << m;
    EXPECT_EQ(m.find(file + "\n", first + 1), std::string::npos) << "named twice:\n" << m;
  }
}

}  // namespace
}  // namespace keel::engine
