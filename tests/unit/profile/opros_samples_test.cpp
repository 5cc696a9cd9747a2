// Every real OPRoS profile in third_party/opros_samples (files published with OPRoS's engine and
// component libraries, kept byte for byte) loads, with exactly the warnings and errors written
// in tests/opros/samples_expected.txt: one block per file, its path and then its diagnostics.
// A change in what keel says of a real file is a change of that file, reviewed there.
// Regenerate it (and read the diff) with KEEL_REGENERATE_OPROS_EXPECTED=1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "profile/loader.hpp"
#include "support/paths.hpp"

namespace keel::profile {
namespace {

namespace fs = std::filesystem;

fs::path samples() { return KEEL_OPROS_SAMPLES; }
fs::path expectedFile() { return fs::path(KEEL_OPROS_TESTS) / "samples_expected.txt"; }

/// "<path>\n" then "  ok" or each diagnostic ("  warning: file:line: ...", "  error: ..."),
/// paths relative to the samples.
std::string describe(const fs::path& file) {
  const std::string prefix = samples().string() + "/";
  auto relative = [&](std::string s) {
    for (auto at = s.find(prefix); at != std::string::npos; at = s.find(prefix, at)) s.erase(at, prefix.size());
    return s;
  };
  std::string out = relative(file.string()) + "\n";
  const auto set = load(file.string());
  if (!set) {
    for (const Diagnostic& d : set.error()) out += "  error: " + relative(d.str()) + "\n";
    return out;
  }
  if (set->warnings.empty()) out += "  ok\n";
  for (const Diagnostic& d : set->warnings) out += "  warning: " + relative(d.str()) + "\n";
  return out;
}

std::vector<fs::path> sampleProfiles() {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(samples()))
    if (e.is_regular_file() && e.path().extension() == ".xml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(OprosSamples, EveryRealProfileLoadsWithTheWarningsWrittenDown) {
  const auto files = sampleProfiles();
  ASSERT_GE(files.size(), 50U) << "the samples are under " << samples();
  std::string actual;
  for (const auto& f : files) actual += describe(f);
  if (std::getenv("KEEL_REGENERATE_OPROS_EXPECTED") != nullptr) {
    std::ofstream(expectedFile()) << actual;
    GTEST_SKIP() << "wrote " << expectedFile();
  }
  std::ifstream in(expectedFile());
  ASSERT_TRUE(in) << "no " << expectedFile() << " (KEEL_REGENERATE_OPROS_EXPECTED=1 writes it)";
  std::stringstream expected;
  expected << in.rdbuf();
  EXPECT_EQ(actual, expected.str());
  EXPECT_EQ(actual.find("  error: "), std::string::npos) << "every real profile loads";
}

}  // namespace
}  // namespace keel::profile
