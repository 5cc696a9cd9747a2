#include "monitor/run_model.hpp"

#include <gtest/gtest.h>

namespace keel::monitor {
namespace {

using nlohmann::json;

Topology pair() {
  return {"demo", {{"producer", "", ""}, {"counter", "", "worker"}}, {{"producer", "out", "counter", "in", "data"}}};
}

const json& componentIn(const json& snapshot, const std::string& name) {
  for (const auto& c : snapshot["components"])
    if (c["name"] == name) return c;
  static const json none;
  return none;
}

TEST(RunModel, StartsFromThePlanWithEveryComponentCreatedAndTheWiring) {
  RunModel model(pair());
  const json s = model.snapshot(5);
  EXPECT_EQ(s["run"], "demo");
  EXPECT_EQ(s["t_ns"], 5);
  EXPECT_EQ(s["emergency"], false);
  ASSERT_EQ(s["components"].size(), 2U);
  EXPECT_EQ(s["components"][0]["name"], "producer") << "in plan order";
  EXPECT_EQ(componentIn(s, "counter")["state"], "Created");
  EXPECT_EQ(componentIn(s, "counter")["process"], "worker");
  ASSERT_EQ(s["connections"].size(), 1U);
  EXPECT_EQ(s["connections"][0]["to_port"], "in");
}

TEST(RunModel, FollowsStatesFaultsAndTheEmergencyLatch) {
  RunModel model(pair());
  EXPECT_TRUE(
      model.apply({{"event", "state"}, {"component", "counter"}, {"from", "Ready"}, {"to", "Active"}, {"t_ns", 10}}));
  EXPECT_TRUE(model.apply({{"event", "detected"}, {"component", "counter"}, {"fault_id", 1}, {"t_ns", 20}}));
  EXPECT_TRUE(model.apply({{"event", "state"}, {"component", "counter"}, {"to", "Error"}, {"pid", 77}, {"t_ns", 21}}));
  EXPECT_FALSE(model.apply({{"event", "diagnosed"}, {"component", "counter"}, {"fault_id", 1}, {"t_ns", 22}}));
  EXPECT_TRUE(model.apply({{"event", "emergency"}, {"phase", "latched"}, {"by", "monitor"}, {"t_ns", 30}}));
  EXPECT_FALSE(model.apply({{"event", "emergency"}, {"phase", "latched"}, {"by", "again"}, {"t_ns", 31}}));

  const json s = model.snapshot(40);
  EXPECT_EQ(componentIn(s, "counter")["state"], "Error");
  EXPECT_EQ(componentIn(s, "counter")["faults"], 1);
  EXPECT_EQ(componentIn(s, "counter")["pid"], 77);
  EXPECT_EQ(componentIn(s, "producer")["faults"], 0);
  EXPECT_EQ(s["emergency"], true);
  EXPECT_EQ(model.lastTime(), 31);

  EXPECT_TRUE(model.apply({{"event", "emergency"}, {"phase", "cleared"}, {"by", "monitor"}}));
  EXPECT_EQ(model.snapshot(50)["emergency"], false);
}

TEST(RunModel, AComponentProcessTakenOverGivesItsMembersTheNewPid) {
  RunModel model(pair());
  EXPECT_TRUE(model.apply({{"event", "host"}, {"process", "worker"}, {"pid", 900}, {"phase", "took_over"}}));
  EXPECT_FALSE(model.apply({{"event", "host"}, {"process", "worker"}, {"pid", 901}, {"phase", "standby"}}));
  EXPECT_EQ(componentIn(model.snapshot(0), "counter")["pid"], 900);
  EXPECT_FALSE(componentIn(model.snapshot(0), "producer").contains("pid"));
}

TEST(RunModel, AComponentThePlanDoesNotNameIsShownAsItAppears) {
  RunModel model(Topology{});
  EXPECT_TRUE(model.apply({{"event", "state"}, {"component", "stray"}, {"to", "Ready"}}));
  EXPECT_EQ(componentIn(model.snapshot(0), "stray")["state"], "Ready");
}

TEST(RunModel, RecordsThatAreNotObjectsOrLackNamesChangeNothing) {
  RunModel model(pair());
  EXPECT_FALSE(model.apply(json::array()));
  EXPECT_FALSE(model.apply({{"event", "state"}}));
  EXPECT_FALSE(model.apply({{"event", "detected"}, {"component", 3}}));
  EXPECT_EQ(model.snapshot(0)["components"].size(), 2U);
}

}  // namespace
}  // namespace keel::monitor
