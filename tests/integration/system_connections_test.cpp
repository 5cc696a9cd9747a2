// A system profile whose applications exchange data: the system's <port_connections> join one
// application's component to another's at run time, and `keel graph` draws the edge.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

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

// keel validate checks a system's own connections against the applications' components: the
// good one passes, and the same system joining a port one application's component lacks is
// refused with the connection's line and the ports it has.
TEST_F(SystemConnections, AreValidatedByKeelValidate) {
  auto good = test::runProcess({KEEL_CLI, "validate", linked()});
  EXPECT_EQ(good.status, 0) << good.err;
  EXPECT_EQ(good.out, linked() + ": ok\n");

  std::string text = test::slurp(linked());
  const std::string dir = std::filesystem::path(linked()).parent_path().string();
  for (const std::string app : {"producer", "consumer"}) {  // the copy elsewhere names them whole
    const std::string ref = "reference=\"" + app + ".xml\"";
    text.replace(text.find(ref), ref.size(), fmt::format("reference=\"{}/{}.xml\"", dir, app));
  }
  const std::string port = "port_name=\"in\"";
  text.replace(text.find(port), port.size(), "port_name=\"inn\"");
  const auto line = std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(text.find("<port_connection ")),
                               '\n') +
                    1;
  const std::string bad = log_ + ".system.xml";
  std::ofstream(bad) << text;
  auto refused = test::runProcess({KEEL_CLI, "validate", bad});
  std::filesystem::remove(bad);
  EXPECT_EQ(refused.status, 2);
  EXPECT_EQ(refused.err,
            bad + ":" + std::to_string(line) +
                ": port_connection: component 'consumer.summer' has no port 'inn' (ports: in, milestones)\n");
  EXPECT_EQ(refused.out, "");
}

}  // namespace
}  // namespace keel::engine
