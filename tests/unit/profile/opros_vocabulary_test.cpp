// OPRoS's profiles as found in the wild (docs/opros.md#what-loads): their encodings and line
// ends, the vocabulary of OPRoS's engine and IDE (accepted; what keel does not act on is a
// warning, once per item and file), its type profiles, and where its assemblies keep the
// profiles they reference. Fixtures in data/opros_dialect/, kept byte for byte by git.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;

constexpr const char* kDir = "opros_dialect/";

std::string at(const std::string& file) { return kDir + file; }

TEST(OprosText, DecodesEucKrAsItsDeclarationSays) {
  const auto set = load(dataPath(at("euc_kr.xml")));
  ASSERT_TRUE(set.ok()) << joined(set);
  EXPECT_EQ(set->components.at(keyOf(at("euc_kr.xml"))).description, "음성 인식");
}

TEST(OprosText, RejectsBytesThatAreNotTheDeclaredEncodingAtTheirLine) {
  EXPECT_THAT(problems(at("not_utf8.xml")),
              ElementsAre("opros_dialect/not_utf8.xml:4: not UTF-8 text: byte 0xC0 (name the file's encoding in its "
                          "XML declaration, e.g. <?xml version=\"1.0\" encoding=\"euc-kr\"?>)"));
}

TEST(OprosText, CountsLinesOfCrlfFilesWithABom) {
  EXPECT_THAT(problems(at("bom_crlf.xml")),
              ElementsAre("opros_dialect/bom_crlf.xml:5: unknown element <nonsense> in <component_profile>"));
}

TEST(OprosText, LoadsAFileWithoutXmlDeclaration) { EXPECT_THAT(warnings(at("no_declaration.xml")), IsEmpty()); }

TEST(OprosVocabulary, AcceptsWhatOPRoSWritesAndWarnsOfWhatKeelDoesNotActOn) {
  // The IDE's ids, canvas and build details, and what OPRoS's engine read and never used, are
  // accepted without a word; each warning is something OPRoS did and keel does not.
  EXPECT_THAT(
      warnings(at("vocabulary/Camera.xml")),
      ElementsAre("opros_dialect/vocabulary/Camera.xml:22: <priority> 127 of component 'Camera' clamped to 99, as "
                  "OPRoS does (priorities are 0 to 99)",
                  "opros_dialect/vocabulary/Camera.xml:28: property 'port' of component 'Camera' must be an int, got "
                  "'COM3': kept as a string, as OPRoS does (it ignores a property's type); a component that reads it "
                  "typed fails to start",
                  "opros_dialect/vocabulary/Camera.xml:48: data port 'spare' dropped: <usage> 'output1' is neither "
                  "input nor output (OPRoS's engine drops such ports too)",
                  "opros_dialect/vocabulary/Camera.xml:55: <exports> in <component_profile> accepted, not used: the "
                  "variables OPRoS's monitor read (EXPORT_VARIABLE); keel's monitor shows ports, states and faults "
                  "(docs/monitor.md)",
                  "opros_dialect/vocabulary/Camera.xml:59: <monitoring> in <component_profile> accepted, not used: "
                  "the variables OPRoS's monitor read (EXPORT_VARIABLE); keel's monitor shows ports, states and "
                  "faults (docs/monitor.md)"));
}

TEST(OprosVocabulary, ReadsWhatOPRoSMeantByIt) {
  const auto set = load(dataPath(at("vocabulary/Camera.xml")));
  ASSERT_TRUE(set.ok()) << joined(set);
  const ComponentProfile& c = set->components.at(keyOf(at("vocabulary/Camera.xml")));
  EXPECT_EQ(c.library_name, "Camera.dll");
  EXPECT_EQ(c.execution.type, ExecutionType::Periodic);
  EXPECT_EQ(c.execution.sharing, Sharing::Shared);
  EXPECT_EQ(c.execution.priority, 99);
  ASSERT_EQ(c.properties.size(), 2U);
  EXPECT_EQ(c.properties[0].type, "string");
  EXPECT_EQ(std::get<std::string>(c.properties[0].value), "COM3");
  EXPECT_EQ(c.properties[1].type, "string") << "no type: a string, as OPRoS passes every property";
  ASSERT_EQ(c.data_ports.size(), 2U) << "the port of usage output1 is dropped";
  EXPECT_EQ(c.data_ports[1].name, "command");
  EXPECT_EQ(c.data_ports[1].queue_policy, QueuePolicy::Fifo) << "<policy>, ETRI's spelling";
  EXPECT_EQ(c.data_ports[1].queue_size, 12U) << "<policy_param name=\"size\">";
}

TEST(OprosVocabulary, ReadsNonPeriodicAsAperiodicAndAnEmptyPeriodAsNotSet) {
  EXPECT_THAT(warnings(at("vocabulary/Aperiodic.xml")),
              ElementsAre("opros_dialect/vocabulary/Aperiodic.xml:3: <type> non-periodic of component 'Aperiodic' "
                          "read as aperiodic, as OPRoS does"));
  const auto set = load(dataPath(at("vocabulary/Aperiodic.xml")));
  ASSERT_TRUE(set.ok());
  EXPECT_EQ(set->components.at(keyOf(at("vocabulary/Aperiodic.xml"))).execution.type, ExecutionType::Aperiodic);
}

TEST(OprosAssembly, FindsProfilesWhereOPRoSsEngineDeploysThemAndWarnsOnce) {
  // hello.xml's profiles are in hello/ (the engine's default deployment); an euc-kr
  // <application_profile> with a commented-out connection followed by a stray '>'.
  EXPECT_THAT(warnings(at("engine/hello.xml")),
              ElementsAre("opros_dialect/engine/hello.xml:6: <node_id> accepted, not used: OPRoS deploys such a "
                          "subcomponent on another node's engine; keel runs it on this machine, in a process of its "
                          "own with <process> (docs/isolation.md)",
                          "opros_dialect/engine/hello.xml:9: text '>' between the elements of <port_connections> "
                          "ignored"));
  const auto set = load(dataPath(at("engine/hello.xml")));
  ASSERT_TRUE(set.ok());
  const PackageProfile* pkg = set->rootPackage();
  ASSERT_NE(pkg, nullptr);
  EXPECT_EQ(pkg->subcomponents[0].reference, keyOf(at("engine/hello/Maker.xml")));
  ASSERT_EQ(pkg->connections.size(), 1U);
  ASSERT_EQ(set->service_types.size(), 1U) << "both ports name one service type file";
  const ServiceTypeProfile& t = set->service_types.begin()->second;
  EXPECT_EQ(t.name, "MessagePrint");
  ASSERT_EQ(t.methods.size(), 2U);
  EXPECT_FALSE(t.methods[0].blocking);
  EXPECT_THAT(t.methods[0].params, ElementsAre(std::pair<std::string, std::string>{"message", "std::string"},
                                               std::pair<std::string, std::string>{"level", "int"}))
      << "in index order, whichever child comes first";
  EXPECT_EQ(t.methods[1].return_type, "int");
}

TEST(OprosAssembly, ChecksAServiceConnectionAgainstBothEndsServiceTypes) {
  // An IDE workspace (App/App.xml, each component in <Name>/profile/): the two components carry
  // different copies of the service type.
  EXPECT_THAT(problems(at("workspace/App/App.xml")),
              ElementsAre("opros_dialect/workspace/App/App.xml:17: port_connection: method 'print' is 'void "
                          "print(std::string, int) nonblocking' in ../Maker/profile/MessagePrint.xml ('maker.print') "
                          "but 'void print(string) nonblocking' in ../Printer/profile/MessagePrint.xml "
                          "('printer.print')",
                          "opros_dialect/workspace/App/App.xml:17: port_connection: 'maker.print' calls method 'count' "
                          "(../Maker/profile/MessagePrint.xml), which 'printer.print' does not provide "
                          "(../Printer/profile/MessagePrint.xml: print)"));
}

TEST(OprosAssembly, WarnsOfAPortThatDisagreesWithItsOwnTypeProfileOrAMissingOne) {
  EXPECT_THAT(warnings(at("workspace/Printer/profile/Printer.xml")),
              ElementsAre("opros_dialect/workspace/Printer/profile/Printer.xml:8: data port 'person' of component "
                          "'Printer' has <data_type> 'PersonData', but its <reference> 'Person.xml' defines "
                          "UserDataType"));
  EXPECT_THAT(warnings(at("workspace/Maker/profile/Maker.xml")),
              ElementsAre("opros_dialect/workspace/Maker/profile/Maker.xml:10: <defined_data_type> of component "
                          "'Maker': cannot read 'Missing.xml' (No such file or directory): nothing is checked "
                          "against it"));
}

TEST(OprosAssembly, NamesEveryPlaceItLookedForAReferenceFoundNowhere) {
  EXPECT_THAT(problems(at("nowhere/App.xml")),
              ElementsAre("opros_dialect/nowhere/App.xml:3: subcomponent 'ghost': cannot open 'Ghost.xml': No such "
                          "file or directory (nor in OPRoS's layouts: App/Ghost.xml, ghost/Ghost.xml, "
                          "App/Ghost/Ghost.xml, ../Ghost/profile/Ghost.xml, ../Ghost/Ghost.xml)"));
}

TEST(OprosTypes, RejectsAServiceTypeWhoseParametersSkipAnIndex) {
  EXPECT_THAT(problems(at("types/Gap.xml")),
              ElementsAre("opros_dialect/types/Gap.xml:2: the <param>s of method 'f' of service type 'Gap' skip index "
                          "2"));
}

TEST(OprosTypes, ABrokenTypeProfileAPortReferencesIsAWarningAndUnused) {
  const auto set = load(dataPath(at("types/UsesGap.xml")));
  ASSERT_TRUE(set.ok()) << joined(set);
  ASSERT_EQ(set->warnings.size(), 1U);
  EXPECT_EQ(relative(set->warnings[0].str()),
            "opros_dialect/types/Gap.xml:2: the <param>s of method 'f' of service type 'Gap' skip index 2 (nothing is "
            "checked against this file)");
  EXPECT_TRUE(set->service_types.empty());
}

TEST(OprosTypes, SaysWhatAnEngineConfigurationIs) {
  const auto set = load(dataPath(at("types/engine_config.xml")));
  ASSERT_TRUE(set.ok()) << joined(set);
  EXPECT_EQ(set->root_kind, RootKind::EngineConfig);
  ASSERT_EQ(set->warnings.size(), 1U);
  EXPECT_THAT(set->warnings[0].message, ::testing::StartsWith("an OPRoS engine's configuration (<system_config>), "
                                                              "not an application"));
}

}  // namespace
}  // namespace keel::profile::test
