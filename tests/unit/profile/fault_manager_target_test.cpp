// keel's system component `fault_manager` as a connection target in a package profile.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "profile/loader.hpp"

namespace keel::profile {
namespace {

class FaultManagerTarget : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "Reporter.xml") << R"(<component_profile>
  <name>Reporter</name>
  <execution_environment><library_name>x</library_name></execution_environment>
  <ports><event_port><name>faults</name><usage>output</usage><data_type>keel::FaultEvent</data_type></event_port></ports>
</component_profile>)";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string package(const std::string& sub_name, const std::string& port) {
    std::ofstream(dir_ / "app.xml") << R"(<package_profile>
  <name>app</name>
  <subcomponents><subcomponent><name>)"
                                    << sub_name
                                    << R"(</name><reference>Reporter.xml</reference></subcomponent></subcomponents>
  <port_connections><port_connection port_type="event">
    <source component_name=")" << sub_name
                                    << R"(" port_name="faults"/>
    <target component_name="fault_manager" port_name=")"
                                    << port << R"("/>
  </port_connection></port_connections>
</package_profile>)";
    return (dir_ / "app.xml").string();
  }
  std::filesystem::path dir_ = std::filesystem::temp_directory_path() / ("keel_fm_" + std::to_string(::getpid()));
};

TEST_F(FaultManagerTarget, AnyPackageMayConnectFaultEventsToIt) {
  auto set = load(package("reporter", "faults"));
  EXPECT_TRUE(set) << (set ? "" : set.error().front().str());
}

TEST_F(FaultManagerTarget, ItHasOnlyTheFaultsPort) {
  auto set = load(package("reporter", "alarms"));
  ASSERT_FALSE(set);
  EXPECT_EQ(set.error().front().message,
            "port_connection: component 'fault_manager' has no port 'alarms' (ports: faults)");
}

TEST_F(FaultManagerTarget, ItsNameIsReserved) {
  auto set = load(package("fault_manager", "faults"));
  ASSERT_FALSE(set);
  bool found = false;
  for (const auto& d : set.error())
    found |= d.message == "subcomponent name 'fault_manager' is reserved for keel's fault manager";
  EXPECT_TRUE(found) << set.error().front().str();
}

}  // namespace
}  // namespace keel::profile
