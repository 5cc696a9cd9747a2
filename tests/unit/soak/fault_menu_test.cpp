// The soak's fault menu and its random scenarios (src/soak/fault_menu): which faults a
// component is offered from its plan, and scenarios keel reads back as written.
#include "soak/fault_menu.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "injection/scenario.hpp"
#include "support/temp_log.hpp"

namespace keel::soak {
namespace {

bool offered(const std::vector<Offer>& menu, const std::string& component, const std::string& kind) {
  return std::any_of(menu.begin(), menu.end(),
                     [&](const Offer& o) { return o.component == component && o.kind == kind; });
}

profile::DataPort port(std::string name, PortDirection usage, std::string type, bool validity) {
  profile::DataPort p;
  p.name = std::move(name);
  p.usage = usage;
  p.data_type = std::move(type);
  if (validity) p.validity = profile::Validity{{0.0}, {10.0}, {}, {}};
  return p;
}

/// sensor (executed, heartbeat, range checked at its output), filter (executed, output checked
/// where it arrives), logger (passive, an unchecked output), vision (in a process).
struct MenuPlan {
  profile::ComponentProfile sensor, filter, logger, vision;
  plan::Plan plan;
  MenuPlan() {
    sensor.data_ports = {port("range", PortDirection::Output, "double", true),
                         port("label", PortDirection::Output, "string", true)};
    filter.data_ports = {port("in", PortDirection::Input, "double", false),
                         port("out", PortDirection::Output, "double", false)};
    logger.data_ports = {port("in", PortDirection::Input, "double", true),
                         port("count", PortDirection::Output, "int", false)};
    plan::PlannedInstance s{"sensor", &sensor, {}, profile::FaultPolicy{}, "", "", {}, {}};
    s.policy->heartbeat_timeout_ms = 200;
    plan.instances = {s,
                      {"filter", &filter, {}, std::nullopt, "", "", {}, {}},
                      {"logger", &logger, {}, std::nullopt, "", "", {}, {}},
                      {"vision", &vision, {}, std::nullopt, "", "vision", {}, {}}};
    plan.connections = {{PortKind::Data, {"sensor", "range"}, {"filter", "in"}, {}},
                        {PortKind::Data, {"filter", "out"}, {"logger", "in"}, {}}};
    plan::PlannedExecutor task;
    task.name = "task";
    task.members = {"sensor", "filter"};
    plan::PlannedExecutor own;
    own.name = "vision";
    own.members = {"vision"};
    plan.executors = {task, own};
  }
};

TEST(SoakFaultMenu, OffersWhatADetectorIsConfiguredToSee) {
  MenuPlan m;
  const std::vector<Offer> menu = faultMenu(m.plan, {{"filter", {"sensor_unplugged 1", "noise"}}});
  for (const char* kind : {"segfault", "divide_by_zero", "abort", "throw", "error_code", "hang", "stall_heartbeat"})
    EXPECT_TRUE(offered(menu, "sensor", kind)) << kind;
  EXPECT_TRUE(offered(menu, "filter", "throw"));
  EXPECT_FALSE(offered(menu, "filter", "hang")) << "no <heartbeat>: nothing would see it";
  EXPECT_FALSE(offered(menu, "logger", "segfault")) << "passive: never executed";
  // out_of_range where a <validity> checks the value: at the port itself, or where it arrives.
  EXPECT_TRUE(offered(menu, "sensor", "out_of_range"));
  EXPECT_TRUE(offered(menu, "filter", "out_of_range"));
  EXPECT_FALSE(offered(menu, "logger", "out_of_range")) << "nothing checks its count";
  EXPECT_EQ(std::count_if(menu.begin(), menu.end(),
                          [](const Offer& o) { return o.component == "sensor" && o.kind == "out_of_range"; }),
            1)
      << "a string port carries no number";
  EXPECT_TRUE(offered(menu, "vision", "kill"));
  EXPECT_FALSE(offered(menu, "sensor", "kill")) << "in keel run's own process";
  const auto stall = std::find_if(menu.begin(), menu.end(), [](const Offer& o) { return o.kind == "stall_heartbeat"; });
  ASSERT_NE(stall, menu.end());
  EXPECT_EQ(stall->duration_ms, 600) << "three heartbeat timeouts";
  const auto unplugged = std::find_if(menu.begin(), menu.end(),
                                      [](const Offer& o) { return o.kind == "sensor_unplugged"; });
  ASSERT_NE(unplugged, menu.end());
  EXPECT_TRUE(unplugged->hardware);
  EXPECT_EQ(unplugged->component, "filter");
  EXPECT_EQ(unplugged->args, "1");
  EXPECT_TRUE(offered(menu, "filter", "noise"));
}

TEST(SoakFaultMenu, ARandomScenarioReadsBackWithEveryKindAtTheRequestedPace) {
  MenuPlan m;
  const std::vector<Offer> menu = faultMenu(m.plan, {{"filter", {"sensor_unplugged 1"}}});
  std::mt19937_64 rng(7);
  const std::string xml = randomScenario(menu, rng, 1000, 100, 61000);
  const std::string path = test::tempPath("keel_soak_scenario", ".xml");
  std::ofstream(path) << xml;
  auto scenario = injection::loadScenario(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(scenario) << scenario.error().front().str() << "\n" << xml;
  const auto& faults = scenario->faults;
  // 60 s at 100 ms on average: 600 give or take what a uniform gap in [50, 150] ms allows.
  EXPECT_GT(faults.size(), 540u);
  EXPECT_LT(faults.size(), 660u);
  EXPECT_GE(faults.front().at_ms, 1000);
  EXPECT_LT(faults.back().at_ms, 61000);
  std::map<std::string, int> kinds;
  for (const auto& f : faults) ++kinds[f.kind_name];
  EXPECT_EQ(kinds.size(), 10u) << "every kind of the menu";
  for (const auto& [kind, n] : kinds) EXPECT_GT(n, 20) << kind << ": each kind about as likely";
  const auto unplugged = std::find_if(faults.begin(), faults.end(), [](const auto& f) { return f.hardware; });
  ASSERT_NE(unplugged, faults.end());
  EXPECT_EQ(unplugged->command(), "sensor_unplugged 1");
  // The same seed draws the same campaign.
  std::mt19937_64 again(7);
  EXPECT_EQ(randomScenario(menu, again, 1000, 100, 61000), xml);
}

}  // namespace
}  // namespace keel::soak
