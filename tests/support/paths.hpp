// Test support: where the tests find what the build made and what the tree holds (the keel CLI,
// component libraries, profiles, scenarios, samples), as absolute paths of this checkout and
// build tree.
//
// They are compiled into tests/support/paths.cpp alone, not into every test file: a test's
// object then holds no path of the checkout, so that ccache serves it to a clone of the tree at
// another path (docs/decisions/0020-ci-time.md). Each name reads as the string it stands for.
#pragma once

namespace keel::test::paths {

const char* source();           // the checkout
const char* cli();              // build/bin/keel
const char* testComponents();   // the test component libraries (tests/integration/components)
const char* stockComponents();  // keel's stock components
const char* oprosComponents();  // OPRoS samples and test components, built unchanged
const char* profileTestData();  // tests/unit/profile/data
const char* testProfiles();     // tests/integration/profiles
const char* scenarios();        // tests/scenarios
const char* examples();         // examples/
const char* oprosSamples();     // third_party/opros_samples
const char* oprosTests();       // tests/opros
const char* motionBoard();      // the simulated motion board's executable
const char* robot();            // robot/
const char* bench();            // keel-bench, the benchmark harness
const char* rclpyPython();      // the test peers' Python, with rclpy (tests/peers/venv)
const char* nodeExec();         // keel-node-exec, what keel run starts a node through

}  // namespace keel::test::paths

#define KEEL_SOURCE_DIR (::keel::test::paths::source())
#define KEEL_CLI (::keel::test::paths::cli())
#define KEEL_TEST_COMPONENTS (::keel::test::paths::testComponents())
#define KEEL_STOCK_COMPONENTS (::keel::test::paths::stockComponents())
#define KEEL_OPROS_COMPONENTS (::keel::test::paths::oprosComponents())
#define KEEL_PROFILE_TEST_DATA (::keel::test::paths::profileTestData())
#define KEEL_TEST_PROFILES (::keel::test::paths::testProfiles())
#define KEEL_SCENARIOS (::keel::test::paths::scenarios())
#define KEEL_EXAMPLES (::keel::test::paths::examples())
#define KEEL_OPROS_SAMPLES (::keel::test::paths::oprosSamples())
#define KEEL_OPROS_TESTS (::keel::test::paths::oprosTests())
#define KEEL_MOTION_BOARD (::keel::test::paths::motionBoard())
#define KEEL_ROBOT (::keel::test::paths::robot())
#define KEEL_BENCH (::keel::test::paths::bench())
#define KEEL_RCLPY_PYTHON (::keel::test::paths::rclpyPython())
#define KEEL_NODE_EXEC (::keel::test::paths::nodeExec())
