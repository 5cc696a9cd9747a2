// System profiles (paper §5.2, Fig. 7): applications over shared, duplicated components, their
// dependencies and health requirements, and every error message with its exact diagnostic.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;

TEST(SystemProfile, ReadsFigureSevenLikeApplications) {
  const auto result = load(dataPath("system/system.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  EXPECT_EQ(result->root_kind, RootKind::System);
  EXPECT_EQ(result->rootPackage(), nullptr);
  ASSERT_TRUE(result->system.has_value());
  const SystemProfile& s = *result->system;
  EXPECT_EQ(s.file, keyOf("system/system.xml"));
  EXPECT_EQ(s.name, "PrototypeRobot");
  ASSERT_EQ(s.applications.size(), 4u);

  const Application& obstacle = s.applications[0];
  EXPECT_EQ(obstacle.name, "obstacle");
  EXPECT_EQ(obstacle.reference, keyOf("system/robot.xml"));
  EXPECT_THAT(obstacle.depends_on, IsEmpty());
  ASSERT_EQ(obstacle.requires_.size(), 1u);
  EXPECT_THAT(obstacle.requires_[0].components, ElementsAre("sonar1", "sonar2", "sonar3"));
  EXPECT_EQ(obstacle.requires_[0].min_healthy, 1);

  const Application& navigation = s.applications[1];
  EXPECT_THAT(navigation.depends_on, ElementsAre("obstacle"));
  ASSERT_EQ(navigation.requires_.size(), 2u);
  EXPECT_EQ(navigation.requires_[0].min_healthy, 2);
  EXPECT_THAT(navigation.requires_[1].components, ElementsAre("nav"));
  EXPECT_EQ(navigation.requires_[1].min_healthy, 1);  // default

  EXPECT_THAT(s.applications[2].requires_, IsEmpty());  // every component needed
  EXPECT_THAT(s.applications[3].depends_on, ElementsAre("hri", "navigation"));
}

TEST(SystemProfile, LoadsEachReferencedPackageOnce) {
  const auto result = load(dataPath("system/system.xml"));
  ASSERT_TRUE(result.ok()) << joined(result);

  EXPECT_EQ(result->packages.size(), 2u);  // robot.xml (two applications) and hri.xml
  EXPECT_EQ(result->packages.at(keyOf("system/robot.xml")).name, "Robot");
  EXPECT_EQ(result->components.size(), 3u);
}

TEST(SystemProfileErrors, RejectsTwoApplicationsWithOneName) {
  EXPECT_THAT(problems("errors/system/duplicate_application.xml"),
              ElementsAre("errors/system/duplicate_application.xml:6: duplicate application 'nav' (first at line 5)"));
}

TEST(SystemProfileErrors, RejectsADependencyOnAnUnknownApplication) {
  EXPECT_THAT(problems("errors/system/depends_on_unknown.xml"),
              ElementsAre("errors/system/depends_on_unknown.xml:6: application 'hri': depends_on 'navv' is not an "
                          "application (applications: nav, hri)"));
}

TEST(SystemProfileErrors, RejectsAnApplicationDependingOnItself) {
  EXPECT_THAT(problems("errors/system/depends_on_self.xml"),
              ElementsAre("errors/system/depends_on_self.xml:5: application 'nav' cannot depend on itself"));
}

TEST(SystemProfileErrors, RejectsADependencyListedTwice) {
  EXPECT_THAT(problems("errors/system/depends_on_twice.xml"),
              ElementsAre("errors/system/depends_on_twice.xml:6: application 'hri' lists depends_on 'nav' twice"));
}

TEST(SystemProfileErrors, RejectsAnEmptyDependsOn) {
  EXPECT_THAT(problems("errors/system/depends_on_empty.xml"),
              ElementsAre("errors/system/depends_on_empty.xml:6: empty <depends_on> in application 'nav'"));
}

TEST(SystemProfileErrors, RejectsCircularApplicationDependencyWithTheCycle) {
  EXPECT_THAT(problems("errors/system/circular_dependency.xml"),
              ElementsAre("errors/system/circular_dependency.xml:8: circular dependency: nav -> hri -> nav"));
}

TEST(SystemProfileErrors, RejectsALongerCycleAndPrintsItInOrder) {
  EXPECT_THAT(problems("errors/system/circular_dependency_long.xml"),
              ElementsAre("errors/system/circular_dependency_long.xml:11: circular dependency: a -> b -> c -> a"));
}

TEST(SystemProfileErrors, RejectsAnApplicationReferencingAComponentProfile) {
  EXPECT_THAT(problems("errors/system/reference_not_package.xml"),
              ElementsAre("errors/system/reference_not_package.xml:5: application 'nav': '../../valid/Sonar.xml' is a "
                          "<component_profile>, expected <package_profile>"));
}

TEST(SystemProfileErrors, RejectsAMissingApplicationProfile) {
  EXPECT_THAT(problems("errors/system/reference_missing.xml"),
              ElementsAre("errors/system/reference_missing.xml:5: application 'nav': cannot open 'nav.xml': No such "
                          "file or directory"));
}

TEST(SystemProfileErrors, RejectsARequiredComponentThePackageDoesNotHave) {
  EXPECT_THAT(problems("errors/system/requires_unknown_component.xml"),
              ElementsAre(
                  "errors/system/requires_unknown_component.xml:6: application 'nav' requires component 'sonar4', "
                  "which package 'Robot' does not have (subcomponents: sonar1, sonar2, sonar3, nav, map)"));
}

TEST(SystemProfileErrors, RejectsMinHealthyAboveTheNumberOfListedComponents) {
  EXPECT_THAT(problems("errors/system/min_healthy_too_large.xml"),
              ElementsAre("errors/system/min_healthy_too_large.xml:6: min_healthy of application 'nav' must be from 1 "
                          "to 2 (the number of listed components), got '3'"));
}

TEST(SystemProfileErrors, RejectsMinHealthyZero) {
  EXPECT_THAT(problems("errors/system/min_healthy_zero.xml"),
              ElementsAre("errors/system/min_healthy_zero.xml:6: min_healthy of application 'nav' must be from 1 to 1 "
                          "(the number of listed components), got '0'"));
}

TEST(SystemProfileErrors, RejectsRequiresWithoutComponents) {
  EXPECT_THAT(problems("errors/system/requires_nothing.xml"),
              ElementsAre(
                  "errors/system/requires_nothing.xml:6: <requires> of application 'nav' lists no <component>"));
}

TEST(SystemProfileErrors, RejectsAComponentRequiredTwice) {
  EXPECT_THAT(problems("errors/system/requires_component_twice.xml"),
              ElementsAre("errors/system/requires_component_twice.xml:8: application 'nav' lists component 'sonar1' "
                          "twice in <requires>"));
}

TEST(SystemProfileErrors, RejectsAnEmptyRequiredComponent) {
  EXPECT_THAT(problems("errors/system/requires_empty_component.xml"),
              ElementsAre("errors/system/requires_empty_component.xml:8: empty <component> in application 'nav'"));
}

TEST(SystemProfileErrors, RejectsAnApplicationWithoutReference) {
  EXPECT_THAT(problems("errors/system/application_missing_reference.xml"),
              ElementsAre(
                  "errors/system/application_missing_reference.xml:5: missing attribute 'reference' of <application>"));
}

TEST(SystemProfileErrors, RejectsAnApplicationWithoutName) {
  EXPECT_THAT(problems("errors/system/application_missing_name.xml"),
              ElementsAre("errors/system/application_missing_name.xml:5: missing attribute 'name' of <application>"));
}

TEST(SystemProfileErrors, RejectsASystemWithoutName) {
  EXPECT_THAT(problems("errors/system/missing_system_name.xml"),
              ElementsAre("errors/system/missing_system_name.xml:2: missing <name> in <system_profile>"));
}

}  // namespace
}  // namespace keel::profile::test
