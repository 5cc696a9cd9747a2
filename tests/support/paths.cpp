// The paths of tests/support/paths.hpp, given by tests/CMakeLists.txt as this file's compile
// definitions. A path a build does not have (keel-bench without the benchmarks) is empty.
#include "support/paths.hpp"

#ifndef KEEL_PATH_BENCH
#define KEEL_PATH_BENCH ""
#endif

namespace keel::test::paths {

const char* source() { return KEEL_PATH_SOURCE; }
const char* cli() { return KEEL_PATH_CLI; }
const char* testComponents() { return KEEL_PATH_TEST_COMPONENTS; }
const char* stockComponents() { return KEEL_PATH_STOCK_COMPONENTS; }
const char* oprosComponents() { return KEEL_PATH_OPROS_COMPONENTS; }
const char* profileTestData() { return KEEL_PATH_PROFILE_TEST_DATA; }
const char* testProfiles() { return KEEL_PATH_TEST_PROFILES; }
const char* scenarios() { return KEEL_PATH_SCENARIOS; }
const char* examples() { return KEEL_PATH_EXAMPLES; }
const char* oprosSamples() { return KEEL_PATH_OPROS_SAMPLES; }
const char* oprosTests() { return KEEL_PATH_OPROS_TESTS; }
const char* motionBoard() { return KEEL_PATH_MOTION_BOARD; }
const char* robot() { return KEEL_PATH_ROBOT; }
const char* bench() { return KEEL_PATH_BENCH; }
const char* rclpyPython() { return KEEL_PATH_RCLPY_PYTHON; }
const char* nodeExec() { return KEEL_PATH_NODE_EXEC; }

}  // namespace keel::test::paths
