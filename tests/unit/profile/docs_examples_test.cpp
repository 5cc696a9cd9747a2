// The examples of docs/profiles.md must load: each ```xml block that is a whole profile is
// written to a scratch directory next to the profiles it references (copies of fixtures) and
// loaded, so the schema reference cannot drift from the reader.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "profile_test_support.hpp"

namespace keel::profile::test {
namespace {

namespace fs = std::filesystem;

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

/// The ```xml blocks that are whole profiles (fragments such as one <port_connection> are not).
std::vector<std::string> profileBlocks(const std::string& markdown) {
  std::vector<std::string> blocks;
  const std::string open = "```xml\n";
  for (auto at = markdown.find(open); at != std::string::npos; at = markdown.find(open, at)) {
    at += open.size();
    const auto end = markdown.find("```", at);
    const std::string block = markdown.substr(at, end - at);
    if (block.find("_profile>") != std::string::npos) blocks.push_back(block);
    at = end;
  }
  return blocks;
}

class DocsExamples : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("keel_docs_examples_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    for (const auto& [from, to] :
         {std::pair{"valid/Sonar.xml", "Sonar.xml"}, std::pair{"valid/SonarBackup.xml", "SonarBackup.xml"},
          std::pair{"valid/Nav.xml", "Nav.xml"}, std::pair{"valid/Voter.xml", "MedianVoter.xml"}}) {
      fs::copy_file(dataPath(from), dir_ / to, fs::copy_options::overwrite_existing);
    }
    write("robot.xml",
          "<package_profile><name>Robot</name><subcomponents>"
          "<subcomponent><name>sonar1</name><reference>Sonar.xml</reference></subcomponent>"
          "<subcomponent><name>sonar2</name><reference>Sonar.xml</reference></subcomponent>"
          "<subcomponent><name>sonar3</name><reference>Sonar.xml</reference></subcomponent>"
          "<subcomponent><name>nav</name><reference>Nav.xml</reference></subcomponent>"
          "</subcomponents></package_profile>");
    write("hri.xml", "<package_profile><name>Hri</name></package_profile>");
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return (dir_ / name).string();
  }

  fs::path dir_;
};

TEST_F(DocsExamples, EveryXmlExampleOfTheSchemaReferenceLoads) {
  const fs::path doc = fs::path(KEEL_PROFILE_TEST_DATA) / "../../../../docs/profiles.md";
  const auto blocks = profileBlocks(readFile(doc));
  ASSERT_EQ(blocks.size(), 4u) << "component, package, composite and system examples in " << doc;

  const char* names[] = {"component.xml", "package.xml", "composite.xml", "system.xml"};
  const RootKind kinds[] = {RootKind::Component, RootKind::Package, RootKind::Composite, RootKind::System};
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const auto result = load(write(names[i], blocks[i]));
    ASSERT_TRUE(result.ok()) << names[i] << ":\n" << joined(result);
    EXPECT_EQ(result->root_kind, kinds[i]) << names[i];
  }
}

}  // namespace
}  // namespace keel::profile::test
