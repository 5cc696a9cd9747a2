// A system profile whose applications exchange data: the system's <port_connections> join one
// application's component to another's at run time, and `keel graph` draws the edge.
#include <gtest/gtest.h>

#include <filesystem>

#include "engine/engine.hpp"
#include "runtime/component_core.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"
#include "support/recording_hooks.hpp"

namespace keel::engine {
namespace {

std::string linked() { return std::string(KEEL_TEST_PROFILES) + "/linked/system.xml"; }

class SystemConnections : public ::testing::Test {
 protected:
  void TearDown() override { std::filesystem::remove(log_); }
  std::string log_ = (std::filesystem::temp_directory_path() /
                      ("keel_system_connections_" + std::to_string(::getpid()) + ".jsonl"))
                         .string();
};

TEST_F(SystemConnections, CarryDataFromOneApplicationsComponentToAnothers) {
  auto set = profile::load(linked());
  ASSERT_TRUE(set) << set.error().front().str();
  EngineOptions eo;
  eo.log_path = log_;
  eo.search_path = {KEEL_TEST_COMPONENTS};
  eo.warn = [](const std::string&) {};
  auto engine = Engine::create(std::move(*set), eo);
  ASSERT_TRUE(engine) << engine.error().message;
  ASSERT_TRUE((*engine)->start());

  // consumer.summer is aperiodic: it executes only when a value arrives, and its one input is
  // the producer application's counter. Its milestones then reach consumer.events, which
  // raises a user fault (naming summer's label) once 30 values have arrived.
  Component* summer = (*engine)->find("consumer.summer");
  ASSERT_NE(summer, nullptr);
  ASSERT_TRUE(test::eventually([&] { return runtime::coreOf(*(*engine)->find("consumer.events")).faults.load() > 0; }));
  EXPECT_GT(runtime::coreOf(*summer).executions.load(), 0u);
  (*engine)->shutdown();

  const auto detected = test::eventsOf(test::readLog(log_), "detected");
  ASSERT_FALSE(detected.empty());
  EXPECT_EQ(detected[0]["component"], "consumer.events");
  EXPECT_EQ(detected[0]["detail"], "milestone 30 reached: from producer");
}

TEST_F(SystemConnections, AreDrawnByKeelGraph) {
  auto r = test::runProcess({KEEL_CLI, "graph", linked()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"producer.counter\" -> \"consumer.summer\" [label=\"count → in\", style=solid];"),
            std::string::npos)
      << r.out;
}

TEST_F(SystemConnections, AreValidatedByKeelValidate) {
  auto r = test::runProcess({KEEL_CLI, "validate", linked()});
  EXPECT_EQ(r.status, 0) << r.err;
}

}  // namespace
}  // namespace keel::engine
