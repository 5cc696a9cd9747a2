// load() as a whole: root kinds, paths, files that cannot be read, XML syntax errors, reference
// kinds and cycles, all problems across files, and that nothing malformed makes it throw.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;
using ::testing::Not;

/// Writes `content` to a scratch file and loads it.
Result<ProfileSet, Diagnostics> loadText(const std::string& content) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("keel_profile_test_" + std::to_string(::getpid()) + ".xml");
  std::ofstream(path, std::ios::binary) << content;
  auto result = load(path.string());
  std::filesystem::remove(path);
  return result;
}

TEST(ProfileLoader, ReportsAMissingRootFileWithoutALine) {
  EXPECT_THAT(problems("errors/loader/nope.xml"),
              ElementsAre("errors/loader/nope.xml: cannot open: No such file or directory"));
}

TEST(ProfileLoader, NormalisesTheRootPathForMessagesAndKeys) {
  EXPECT_THAT(problems("errors/../errors/loader/syntax.xml"),
              ElementsAre("errors/loader/syntax.xml:5: XML syntax error: Start-end tags mismatch"));
  const auto result = load(dataPath("valid/../valid/app.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);
  EXPECT_EQ(result->root, keyOf("valid/app.xml"));
  EXPECT_TRUE(std::filesystem::path(result->root).is_absolute());
}

TEST(ProfileLoader, ReportsTheRootKindOfEachProfile) {
  EXPECT_EQ(load(dataPath("valid/Sonar.xml"))->root_kind, RootKind::Component);
  EXPECT_EQ(load(dataPath("valid/SonarArray.xml"))->root_kind, RootKind::Composite);
  EXPECT_EQ(load(dataPath("valid/app.xml"))->root_kind, RootKind::Package);
  EXPECT_EQ(load(dataPath("opros/VisionApp.xml"))->root_kind, RootKind::Package);
  EXPECT_EQ(load(dataPath("system/system.xml"))->root_kind, RootKind::System);
}

TEST(ProfileLoader, FormatsDiagnosticsAsFileLineMessage) {
  EXPECT_EQ((Diagnostic{Where{"app.xml", 14}, "bad"}.str()), "app.xml:14: bad");
  EXPECT_EQ((Diagnostic{Where{"app.xml", 0}, "bad"}.str()), "app.xml: bad");
  EXPECT_EQ((Diagnostic{Where{"", 0}, "bad"}.str()), "bad");
}

TEST(ProfileLoader, NeverThrowsOnMalformedInput) {
  const std::string inputs[] = {
      "",
      "<",
      std::string("\0\x01\xff<component_profile>", 22),  // a NUL first
      "<component_profile><name>x</name><ports><data_port/></ports></component_profile>",
      std::string("<package_profile><subcomponents><subcomponent><name>a</name><reference>/dev/zero") +
          "</reference></subcomponent></subcomponents></package_profile>",
      std::string(20000, '<'),
      [] {
        std::string deep;
        for (int i = 0; i < 5000; ++i) deep += "<copyright>";
        for (int i = 0; i < 5000; ++i) deep += "</copyright>";
        return "<component_profile><name>x</name>" + deep + "</component_profile>";
      }(),
  };
  for (const std::string& input : inputs) {
    Result<ProfileSet, Diagnostics> result = Diagnostics{};
    EXPECT_NO_THROW(result = loadText(input));
    if (!result.ok()) {
      EXPECT_THAT(result.error(), Not(IsEmpty()));
    }
  }
}

TEST(ProfileLoader, ReportsAnXmlSyntaxErrorWithItsLine) {
  EXPECT_THAT(problems("errors/loader/syntax.xml"),
              ElementsAre("errors/loader/syntax.xml:5: XML syntax error: Start-end tags mismatch"));
}

TEST(ProfileLoader, ReportsAnXmlSyntaxErrorInAReferencedFileAtThatFile) {
  EXPECT_THAT(problems("errors/loader/syntax_in_reference.xml"),
              ElementsAre("errors/loader/syntax.xml:5: XML syntax error: Start-end tags mismatch"));
}

TEST(ProfileLoader, RejectsAnUnknownRootElement) {
  EXPECT_THAT(problems("errors/loader/unknown_root.xml"),
              ElementsAre(
                  "errors/loader/unknown_root.xml:2: unknown root element <robot> (expected <component_profile>, "
                  "<composite_component_profile>, <package_profile>, <system_profile>, <ros2_node_profile>, "
                  "<service_port_type_profile>, <data_type> or <system_config>)"));
}

TEST(ProfileLoader, RejectsASecondRootElement) {
  EXPECT_THAT(problems("errors/loader/second_root.xml"),
              ElementsAre(
                  "errors/loader/second_root.xml:5: second root element <component_profile> (a profile has one)"));
}

TEST(ProfileLoader, RejectsADirectoryAsReference) {
  EXPECT_THAT(problems("errors/loader/reference_is_directory.xml"),
              ElementsAre(
                  "errors/loader/reference_is_directory.xml:5: subcomponent 'p': cannot open '.': is a directory"));
}

TEST(ProfileLoader, RejectsASystemProfileAsSubcomponent) {
  EXPECT_THAT(problems("errors/loader/system_as_subcomponent.xml"),
              ElementsAre("errors/loader/system_as_subcomponent.xml:5: subcomponent 'p': '../../system/system.xml' is "
                          "a <system_profile>, expected <component_profile>, <composite_component_profile> or "
                          "<ros2_node_profile>"));
}

TEST(ProfileLoader, RejectsAPackageIncludingItself) {
  EXPECT_THAT(problems("errors/loader/package_includes_itself.xml"),
              ElementsAre(
                  "errors/loader/package_includes_itself.xml:5: subcomponent 'p': 'package_includes_itself.xml' is a "
                  "<package_profile>, expected <component_profile>, <composite_component_profile> or "
                  "<ros2_node_profile>"));
}

TEST(ProfileLoader, ReportsAllProblemsAcrossFilesNotJustTheFirst) {
  // Grouped by file in load order (the root first), each file in line order.
  EXPECT_THAT(
      problems("errors/many/app.xml"),
      ElementsAre("errors/many/app.xml:9: <severity> of fault_policy of subcomponent 'bad' must be one of ignore, "
                  "reset, stop or emergency, got 'explode'",
                  "errors/many/app.xml:10: timeout of <heartbeat> of fault_policy of subcomponent 'bad' must be a "
                  "positive number, got '-1'",
                  "errors/many/app.xml:17: property 'speed' of subcomponent 'nav' must be a finite double, got 'quick'",
                  "errors/many/app.xml:22: subcomponent 'ghost': cannot open 'Ghost.xml': No such file or directory "
                  "(nor in OPRoS's layouts: app/Ghost.xml, ghost/Ghost.xml, app/Ghost/Ghost.xml, "
                  "../Ghost/profile/Ghost.xml, ../Ghost/Ghost.xml)",
                  "errors/many/app.xml:26: port_connection: component 'nav' has no port 'rang' (ports: range, limit, "
                  "alarm, map)",
                  "errors/many/app.xml:32: period of task 'control' must be a positive number, got '0'",
                  "errors/many/app.xml:32: task 'control': no subcomponent 'nobody' (subcomponents: bad, nav, ghost)",
                  "errors/many/Bad.xml:5: <period> of component 'Bad' must be a positive number, got 'fast'",
                  "errors/many/Bad.xml:12: <queue_size> of data port 'out' must be a positive integer, got '-3'"));
}

}  // namespace
}  // namespace keel::profile::test
