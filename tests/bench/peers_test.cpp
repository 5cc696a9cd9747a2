// The peers `keel bench recovery` measures beside keel (bench/harness/peers.hpp): each recovers
// every fault it is given with a plausible latency, leaves no child process, descriptor or
// temporary directory behind, runs under SCHED_FIFO or says why not, and says why when it
// cannot run at all. No timing goals: the numbers are the harness's business.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <stdlib.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "peers.hpp"
#include "support/env.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;

namespace keel::bench {
namespace {

constexpr int kFaults = 20;

/// Where keel-bench finds its peers, from the keel-bench this test binary was built with.
Paths benchPaths() {
  const fs::path bin = fs::path(KEEL_BENCH).parent_path();
  Paths p;
  p.bin = bin.string();
  p.peers = (bin.parent_path() / "share" / "keel" / "bench" / "peers").string();
  p.child = (bin / "keel-bench-child").string();
  return p;
}

/// Processes (zombies included) whose parent is this one.
int childCount() {
  int count = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/proc", ec)) {
    std::ifstream stat(entry.path() / "stat");
    std::string line;
    if (!std::getline(stat, line)) continue;
    const auto close = line.rfind(')');  // "pid (comm) state ppid ...": comm may hold spaces
    if (close == std::string::npos) continue;
    std::istringstream fields(line.substr(close + 1));
    char state = 0;
    long ppid = 0;
    if (fields >> state >> ppid && ppid == getpid()) ++count;
  }
  return count;
}

int openFdCount() {
  int count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator("/proc/self/fd")) ++count;
  return count;
}

void expectEveryFaultRecovered(const PeerResult& r, int n) {
  ASSERT_EQ(r.skipped, "");
  EXPECT_EQ(r.failed, 0u);
  ASSERT_EQ(r.latencies_ns.size(), static_cast<std::size_t>(n));
  for (const std::int64_t ns : r.latencies_ns) {
    EXPECT_GT(ns, 0);
    EXPECT_LT(ns, 1'000'000'000);
  }
}

/// An empty directory of this test's own, removed after.
struct EmptyDir {
  fs::path path;
  EmptyDir() {
    std::string tmpl = (fs::temp_directory_path() / "keel-peers-test-XXXXXX").string();
    if (mkdtemp(tmpl.data()) != nullptr) path = tmpl;
  }
  ~EmptyDir() { fs::remove_all(path); }
  EmptyDir(const EmptyDir&) = delete;
  EmptyDir& operator=(const EmptyDir&) = delete;
  EmptyDir(EmptyDir&&) = delete;
  EmptyDir& operator=(EmptyDir&&) = delete;
  bool empty() const { return fs::is_empty(path); }
};

bool erlangMissing(const PeerResult& r) { return r.skipped.starts_with("erl not found"); }

int schedulerOfThisThread() {
  int policy = -1;
  sched_param param{};
  pthread_getschedparam(pthread_self(), &policy, &param);
  return policy;
}

TEST(PeerRespawn, RecoversEveryCrashAndLeavesNoChildOrDescriptor) {
  const int fds = openFdCount();

  const PeerResult r = runRespawnPeer(benchPaths(), kFaults, false);

  expectEveryFaultRecovered(r, kFaults);
  EXPECT_EQ(childCount(), 0);
  EXPECT_EQ(openFdCount(), fds);
}

TEST(PeerRespawn, UnderFifoRunsOrSaysWhyNotAndLeavesTheCallerAsItWas) {
  const int policy = schedulerOfThisThread();

  const PeerResult r = runRespawnPeer(benchPaths(), 5, true);

  if (r.skipped.empty()) expectEveryFaultRecovered(r, 5);
  else EXPECT_NE(r.skipped.find("SCHED_FIFO not permitted"), std::string::npos) << r.skipped;
  EXPECT_EQ(schedulerOfThisThread(), policy);
  EXPECT_EQ(childCount(), 0);
}

TEST(PeerRespawn, AMissingChildProgramIsSkippedWithItsPath) {
  Paths paths = benchPaths();
  paths.child = "/nonexistent/keel-bench-child";

  const PeerResult r = runRespawnPeer(paths, kFaults, false);

  EXPECT_EQ(r.skipped, "keel-bench-child not found at /nonexistent/keel-bench-child");
  EXPECT_TRUE(r.latencies_ns.empty());
}

TEST(PeerRespawn, AChildThatNeverReportsReadyIsSkippedWithinTheBoundAndReaped) {
  Paths paths = benchPaths();
  paths.child = "/bin/cat";  // reads its commands and echoes them: never "ready <ns>"

  const PeerResult r = runRespawnPeer(paths, kFaults, false);

  EXPECT_EQ(r.skipped, "keel-bench-child did not report ready within 2 s");
  EXPECT_EQ(childCount(), 0);
}

TEST(PeerErlang, RestartsEveryCrashedWorkerAndLeavesNothingBehind) {
  const EmptyDir tmp;
  const keel::test::ScopedEnv tmpdir("TMPDIR", tmp.path.string());  // where the compiled peer goes
  const int fds = openFdCount();

  const PeerResult r = runErlangPeer(benchPaths(), kFaults, false);

  if (erlangMissing(r)) GTEST_SKIP() << r.skipped;
  expectEveryFaultRecovered(r, kFaults);
  EXPECT_TRUE(r.detail.starts_with("OTP ")) << r.detail;
  EXPECT_EQ(childCount(), 0);
  EXPECT_EQ(openFdCount(), fds);
  EXPECT_TRUE(tmp.empty());
}

TEST(PeerErlang, UnderFifoRunsOrSaysWhyNot) {
  const PeerResult r = runErlangPeer(benchPaths(), 5, true);

  if (erlangMissing(r)) GTEST_SKIP() << r.skipped;
  if (r.skipped.empty()) expectEveryFaultRecovered(r, 5);
  else EXPECT_NE(r.skipped.find("SCHED_FIFO not permitted"), std::string::npos) << r.skipped;
  EXPECT_EQ(childCount(), 0);
}

TEST(PeerErlang, WithoutErlOnThePathIsSkippedWithTheInstallHint) {
  const EmptyDir nothing;
  const keel::test::ScopedEnv path("PATH", nothing.path.string());

  const PeerResult r = runErlangPeer(benchPaths(), kFaults, false);

  EXPECT_EQ(r.skipped, "erl not found (scripts/deps.sh installs erlang-base)");
}

TEST(PeerErlang, WithoutItsSourcesIsSkippedNamingTheDirectory) {
  const EmptyDir nothing;
  Paths paths = benchPaths();
  paths.peers = nothing.path.string();

  const PeerResult r = runErlangPeer(paths, kFaults, false);

  if (erlangMissing(r)) GTEST_SKIP() << r.skipped;
  EXPECT_EQ(r.skipped, "no Erlang peer sources in " + nothing.path.string());
}

TEST(PeerErlang, SourcesThatDoNotCompileAreSkippedWithErlcsMessage) {
  const EmptyDir broken;
  std::ofstream(broken.path / "keel_bench_sup.erl") << "-module(keel_bench_sup).\nmain( ->\n";
  Paths paths = benchPaths();
  paths.peers = broken.path.string();

  const PeerResult r = runErlangPeer(paths, kFaults, false);

  if (erlangMissing(r)) GTEST_SKIP() << r.skipped;
  EXPECT_TRUE(r.skipped.starts_with("erlc failed: ")) << r.skipped;
  EXPECT_NE(r.skipped.find("keel_bench_sup.erl:2"), std::string::npos) << r.skipped;
  EXPECT_EQ(childCount(), 0);
}

}  // namespace
}  // namespace keel::bench
