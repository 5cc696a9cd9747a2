// keel run --monitor and --record given what they cannot use: a clear message, and the right
// exit, before anything runs (docs/bad-input.md).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>

#include "support/env.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"
#include "support/temp_log.hpp"

namespace keel {
namespace {

std::string profile(const std::string& name) { return std::string(KEEL_TEST_PROFILES) + "/" + name; }

class MonitorCli : public ::testing::Test {
 protected:
  keel::test::ScopedEnv component_path_{"KEEL_COMPONENT_PATH", KEEL_TEST_COMPONENTS};
};

TEST_F(MonitorCli, AMonitorAddressThatIsNoPortIsRefusedBeforeAnythingLoads) {
  for (const char* bad : {"nonsense", "127.0.0.1:", "127.0.0.1:99999", "[::1]8765"}) {
    auto r = test::runProcess({KEEL_CLI, "run", profile("pipeline.xml"), "--duration", "5", "--monitor", bad});
    EXPECT_EQ(r.status, 2) << bad << "\n" << r.err;
    EXPECT_NE(r.err.find(std::string("--monitor '") + bad + "'"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("monitor: "), std::string::npos) << "nothing served";
  }
}

TEST_F(MonitorCli, APortInUseIsAnErrorNamingItAndNothingRuns) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in at{};
  at.sin_family = AF_INET;
  at.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&at), sizeof at), 0);
  ASSERT_EQ(::listen(fd, 1), 0);
  socklen_t len = sizeof at;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&at), &len);
  const std::string port = std::to_string(ntohs(at.sin_port));

  auto r = test::runProcess({KEEL_CLI, "run", profile("pipeline.xml"), "--duration", "5", "--monitor", port});
  ::close(fd);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("cannot listen on 127.0.0.1:" + port), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("faults"), std::string::npos) << "no run, no summary:\n" << r.out;
}

TEST_F(MonitorCli, ARecordingThatCannotBeWrittenIsAnErrorNamingTheFile) {
  auto r = test::runProcess(
      {KEEL_CLI, "run", profile("pipeline.xml"), "--duration", "5", "--record", "/nonexistent/dir/run.mcap"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("--record"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/dir/run.mcap"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace keel
