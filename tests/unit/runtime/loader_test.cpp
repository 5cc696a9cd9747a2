// Where the loader looks for component libraries by default (docs/author-api.md): each directory
// of KEEL_COMPONENT_PATH in order (separated by `:`), then <directory of libkeel.so>/keel.
#include "runtime/loader.hpp"
#include "support/env.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace keel::runtime {
namespace {

/// Sets KEEL_COMPONENT_PATH for one test and puts back what was there.
struct ComponentPathEnv : test::ScopedEnv {
  explicit ComponentPathEnv(const char* value) : test::ScopedEnv("KEEL_COMPONENT_PATH", value) {}
};

TEST(LoaderSearchPath, HasEveryDirectoryOfTheComponentPathInOrderThenKeelsOwn) {
  const ComponentPathEnv env("/opt/a::/opt/b:/opt/c:");
  const std::vector<std::string> path = Loader::defaultSearchPath();
  ASSERT_EQ(path.size(), 4u) << ::testing::PrintToString(path);
  EXPECT_EQ(path[0], "/opt/a");
  EXPECT_EQ(path[1], "/opt/b");  // an empty entry names nothing
  EXPECT_EQ(path[2], "/opt/c");
  EXPECT_TRUE(path[3].ends_with("/keel")) << path[3];  // beside libkeel.so
}

}  // namespace
}  // namespace keel::runtime
