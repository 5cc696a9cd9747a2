// The test robot's profiles declare its components twice: robot/navigation.xml (Fig. 5, one
// package) and robot/apps/*.xml (the same components split into Fig. 7's applications for
// robot/system.xml). This keeps the two from drifting apart: the same subcomponents, each with
// the same component profile, properties (up to the applications' name prefixes), fault policy
// and process.
#include <gtest/gtest.h>

#include <pugixml.hpp>

#include <filesystem>
#include <map>
#include <string>

#include "support/paths.hpp"

namespace {

namespace fs = std::filesystem;

/// name -> a canonical text of the subcomponent: reference file name, properties, fault policy.
std::map<std::string, std::string> subcomponents(const fs::path& file) {
  pugi::xml_document doc;
  EXPECT_TRUE(doc.load_file(file.c_str())) << file;
  std::map<std::string, std::string> out;
  for (pugi::xml_node s : doc.child("package_profile").child("subcomponents").children("subcomponent")) {
    std::string text = fs::path(s.child_value("reference")).filename().string() + "|";
    for (pugi::xml_node p : s.child("properties").children("property")) {
      std::string value = p.child_value();
      for (const char* app : {"navigation.", "obstacle_detection.", "hri."})
        for (std::size_t at; (at = value.find(app)) != std::string::npos;) value.erase(at, std::string(app).size());
      text += std::string(p.attribute("name").value()) + "=" + value + ";";
    }
    for (pugi::xml_node f : s.child("fault_policy").children()) {
      text += std::string("|") + f.name() + ":" + f.child_value();
      for (pugi::xml_attribute a : f.attributes()) {
        std::string v = a.value();
        if (std::string(a.name()) == "reference") v = fs::path(v).filename().string();
        text += std::string(" ") + a.name() + "=" + v;
      }
    }
    for (pugi::xml_node p : s.children("process"))
      text += std::string("|process ") + p.attribute("name").value() + " standby=" + p.attribute("standby").value();
    out[s.child_value("name")] = text;
  }
  return out;
}

TEST(RobotProfiles, TheFig7ApplicationsHoldExactlyTheComponentsAndPoliciesOfTheFig5Package) {
  const fs::path robot = fs::path(KEEL_PROFILE_TEST_DATA).parent_path().parent_path().parent_path().parent_path() /
                         "robot";
  const auto package = subcomponents(robot / "navigation.xml");
  std::map<std::string, std::string> apps;
  for (const char* app : {"obstacle_detection.xml", "path_planning.xml", "hri.xml"})
    for (const auto& [name, text] : subcomponents(robot / "apps" / app)) {
      EXPECT_EQ(apps.count(name), 0u) << name << " is in two applications";
      apps[name] = text;
    }
  ASSERT_EQ(package.size(), 14u);
  EXPECT_EQ(apps, package);
}

}  // namespace
