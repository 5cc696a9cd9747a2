// The kill -9 campaign (docs/kill-9.md): `keel run` of the robot, with faults coming all the
// time, is killed at 100 random moments, from its first instants (while it starts) to a few
// seconds in.
// After each kill: the log reads, line by line, up to its last complete line; every record a
// second channel (the log's tee, a pipe the test reads all along) saw is in the log; nothing
// keel started is still running; nothing is left in /dev/shm or in the run's directory; and
// the next run starts. KEEL_KILLED_RUNS sets the count, KEEL_KILL_SEED the moments.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/pipe_reader.hpp"
#include "support/process.hpp"

namespace keel::test {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A fault about every 100 ms of the engine's first 3.1 s, in both processes: crashes and
// exceptions (reset), hangs the watchdogs catch, kills of the vision process (its standby takes
// over), an unplugged and a lying sonar (stopped), an avoidance that escalates to its alternative.
// Each component gets a fault a second at most: more than 3 recoveries in 10 s escalate to a
// stop (the default restart intensity), which comes at the end of the window.
constexpr char kScenario[] = R"(<?xml version="1.0" encoding="UTF-8"?>
<fault_scenario>
  <fault at="50" component="planner" kind="throw" repeat="4" every="1000"/>
  <fault at="150" component="camera" kind="segfault" repeat="4" every="1000"/>
  <fault at="250" component="sonar_frame" kind="error_code" repeat="4" every="1000"/>
  <fault at="350" component="detector" kind="kill" repeat="2" every="1400"/>
  <fault at="450" component="voter" kind="divide_by_zero" repeat="4" every="1000"/>
  <fault at="550" component="avoidance" kind="throw" repeat="4" every="1000"/>
  <fault at="650" component="actuator" kind="hang" repeat="2" every="1400"/>
  <fault at="750" component="sonar_a" kind="segfault" repeat="3" every="1000"/>
  <fault at="850" component="wheel_model" kind="throw" repeat="3" every="1000"/>
  <fault at="950" component="detector" kind="segfault"/>
  <fault at="1150" component="actuator" kind="sensor_unplugged" args="1"/>
  <fault at="1450" component="sonar_c" kind="out_of_range" port="range" value="0"/>
  <fault at="2650" component="detector" kind="hang"/>
</fault_scenario>
)";

constexpr char kStarted[] = R"("phase":"started")";

unsigned long fromEnvironment(const char* name, unsigned long otherwise) {
  const char* v = std::getenv(name);
  return v ? std::strtoul(v, nullptr, 10) : otherwise;
}

std::set<std::string> entriesOf(const fs::path& dir) {
  std::set<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) out.insert(e.path().filename().string());
  return out;
}

/// This process's children that are alive (and reaps those that ended). It is a subreaper
/// during the campaign: what keel run leaves behind when it dies becomes its child.
std::vector<std::pair<long, std::string>> liveChildren() {
  while (::waitpid(-1, nullptr, WNOHANG) > 0) {}
  std::vector<std::pair<long, std::string>> live;
  for (const auto& child : childrenOf(::getpid()))
    if (!processGone(child.first)) live.push_back(child);
  return live;
}

/// What of keel's is still running: children of this process, processes that mention `dir`.
std::string leftRunning(const fs::path& dir) {
  std::string out;
  for (const auto& [pid, comm] : liveChildren()) out += fmt::format(" {} (pid {})", comm, pid);
  for (long pid : processesMentioning(dir.string()))
    if (!processGone(pid)) out += fmt::format(" pid {} mentioning {}", pid, dir.string());
  return out;
}

/// leftRunning(dir) once it is "", or after `within`.
std::string leftRunningAfter(const fs::path& dir, std::chrono::milliseconds within) {
  std::string left;
  for (const auto until = Clock::now() + within; Clock::now() < until; std::this_thread::sleep_for(10ms)) {
    left = leftRunning(dir);
    if (left.empty()) break;
  }
  return left;
}

void killAll(const fs::path& dir) {
  for (const auto& child : liveChildren()) ::kill(static_cast<pid_t>(child.first), SIGKILL);
  for (long pid : processesMentioning(dir.string())) ::kill(static_cast<pid_t>(pid), SIGKILL);
  std::this_thread::sleep_for(100ms);
  (void)liveChildren();
}

/// The first line of `teed` that `logged` lacks (as multisets of exact lines), or "".
std::string notInLog(std::vector<std::string> teed, std::vector<std::string> logged) {
  std::sort(teed.begin(), teed.end());
  std::sort(logged.begin(), logged.end());
  std::vector<std::string> missing;
  std::set_difference(teed.begin(), teed.end(), logged.begin(), logged.end(), std::back_inserter(missing));
  return missing.empty() ? "" : fmt::format("{} line(s), the first: {}", missing.size(), missing.front());
}

/// The campaign's directory and files, and what it counts; cleans up after itself.
struct KillCampaign {
  KillCampaign()
      : dir(fs::temp_directory_path() / ("keel_kill_campaign_" + std::to_string(::getpid()))),
        scenario((dir / "scenario.xml").string()), log((dir / "run.jsonl").string()), out((dir / "out.txt").string()),
        err((dir / "err.txt").string()) {
    fs::create_directories(dir);
    std::ofstream(scenario) << kScenario;
    ::prctl(PR_SET_CHILD_SUBREAPER, 1);
  }
  ~KillCampaign() {
    killAll(dir);
    for (const auto& e : entriesOf("/dev/shm"))  // what a failed kill left there, once seen
      for (long pid : ours)
        if (e.size() > std::to_string(pid).size() && e.ends_with("-" + std::to_string(pid)))
          fs::remove("/dev/shm/" + e);
    ::prctl(PR_SET_CHILD_SUBREAPER, 0);
    if (!::testing::Test::HasFailure()) fs::remove_all(dir);  // kept for a look when something failed
  }
  KillCampaign(const KillCampaign&) = delete;
  KillCampaign& operator=(const KillCampaign&) = delete;

  std::vector<std::string> argv(const std::string& tee, int seed, const std::string& duration = "60") const {
    return {KEEL_CLI,
            "run",
            std::string(KEEL_ROBOT) + "/navigation.xml",
            "--duration",
            duration,
            "--log",
            log,
            "--log-tee",
            tee,
            "--inject",
            scenario,
            "--set",
            "actuator.seed=" + std::to_string(seed),
            "--set",
            "camera.seed=" + std::to_string(seed)};
  }

  /// Everything one kill may not leave; each problem is a test failure.
  void check(PipeReader& tee, const std::set<std::string>& shm_before) {
    const std::string left = leftRunningAfter(dir, 5s);  // the board looks every 20 ms
    EXPECT_EQ(left, "") << "still running 5 s after keel run was killed";
    if (!left.empty()) killAll(dir);
    EXPECT_TRUE(tee.finish(2s)) << "a process still holds the tee's pipe";

    const LogLines logged = readLogLines(log);
    EXPECT_EQ(logged.problem, "") << log;
    const std::vector<std::string> teed = linesOf(tee.text());
    EXPECT_EQ(notInLog(teed, logged.lines), "") << "records seen on the tee and missing from the log " << log;
    EXPECT_TRUE(tee.text().empty() || tee.text().back() == '\n') << "a partial line on the tee";
    lines_logged += logged.lines.size();
    lines_teed += teed.size();
    partial_last_lines += !logged.partial.empty();

    EXPECT_EQ(newInShm(shm_before), "");
    std::set<std::string> others = entriesOf(dir);  // no log when keel run died before it made it
    for (const char* ours_too : {"scenario.xml", "run.jsonl", "out.txt", "err.txt"}) others.erase(ours_too);
    std::string named;
    for (const auto& f : others) named += " " + f;
    EXPECT_EQ(named, "") << "in " << dir;
  }

  /// What /dev/shm has that it had not before (the robot's truth file is keel-robot-<keel run's
  /// pid>): "" when nothing. An entry named after a live process of another user's run beside
  /// this one is not the campaign's.
  std::string newInShm(const std::set<std::string>& before) const {
    std::string found;
    for (const auto& e : entriesOf("/dev/shm")) {
      if (before.count(e)) continue;
      const auto dash = e.rfind('-');
      const std::string pid = dash == std::string::npos ? "" : e.substr(dash + 1);
      const bool named = !pid.empty() && pid.size() < 10 && pid.find_first_not_of("0123456789") == std::string::npos;
      if (named && !ours.count(std::stol(pid)) && !processGone(std::stol(pid))) continue;
      found += " " + e;
    }
    return found;
  }

  /// Keeps the failed kill's files beside the next run's.
  void keep(int kill, const PipeReader& tee) const {
    std::error_code absent;
    fs::copy_file(log, dir / fmt::format("kill_{}.jsonl", kill), fs::copy_options::overwrite_existing, absent);
    std::ofstream(dir / fmt::format("kill_{}.tee", kill)) << tee.text();
    fs::copy_file(err, dir / fmt::format("kill_{}.err", kill), fs::copy_options::overwrite_existing, absent);
  }

  fs::path dir;
  std::string scenario, log, out, err;
  std::set<long> ours;  // every keel run started
  std::size_t lines_logged = 0, lines_teed = 0, partial_last_lines = 0;
};

TEST(KilledRun, HundredKillsAtRandomMomentsLoseNoRecordAndLeaveNothingBehind) {
  const auto kills = static_cast<int>(fromEnvironment("KEEL_KILLED_RUNS", 100));
  const auto seed = static_cast<unsigned>(fromEnvironment("KEEL_KILL_SEED", std::random_device{}()));
  SCOPED_TRACE(fmt::format("seed {} (KEEL_KILL_SEED={} repeats these moments)", seed, seed));
  std::mt19937 random(seed);
  std::bernoulli_distribution while_starting(0.25);
  std::uniform_int_distribution<int> starting_ms(0, 119), running_ms(0, 2999);  // keel run starts in ~50 ms
  const std::set<std::string> shm_before = entriesOf("/dev/shm");
  KillCampaign c;
  ASSERT_EQ(leftRunning(c.dir), "") << "before the campaign";

  const auto campaign_start = Clock::now();
  int done = 0, before_started = 0, ended_by_itself = 0, held_to_start = 0;
  bool must_start = false;  // the run after a kill during startup must itself start
  for (int i = 1; i <= kills; ++i) {
    const int moment_ms = while_starting(random) ? starting_ms(random) : running_ms(random);
    SCOPED_TRACE(fmt::format("kill {} of {}, {} ms after keel run was started", i, kills, moment_ms));
    PipeReader tee;
    ASSERT_TRUE(tee.ok());
    fs::remove(c.log);  // a run killed before it made its log leaves none, not the last one's
    const pid_t keel = startProcess(c.argv(tee.path(), i), c.out, c.err);
    c.ours.insert(keel);
    const auto start = Clock::now();
    int status = 0;
    bool ended = false;
    while (!ended && Clock::now() < start + std::chrono::milliseconds(moment_ms)) {
      std::this_thread::sleep_for(1ms);
      ended = ::waitpid(keel, &status, WNOHANG) == keel;
    }
    bool started = tee.waitFor(kStarted, 0ms);
    if (!ended && must_start && !started) {
      ++held_to_start;
      started = tee.waitFor(kStarted, 30s);
      EXPECT_TRUE(started) << "the run after a kill during startup did not start: " << slurp(c.err);
    }
    if (!ended) {
      ::kill(keel, SIGKILL);
      ::waitpid(keel, &status, 0);
    } else {
      ++ended_by_itself;  // not a kill: its log was checked all the same
    }
    ++done;
    before_started += !started;
    must_start = !started;
    c.check(tee, shm_before);
    if (::testing::Test::HasFailure()) {
      c.keep(i, tee);
      break;
    }
  }
  const double took_s = std::chrono::duration<double>(Clock::now() - campaign_start).count();

  // One last run, to its end: it starts, runs and stops as if nothing had happened before.
  PipeReader tee;
  auto last = runProcess(c.argv(tee.path(), kills + 1, "1"));
  EXPECT_EQ(last.status, 0) << last.err;
  EXPECT_TRUE(tee.finish(5s));
  const LogLines log = readLogLines(c.log);
  EXPECT_EQ(log.problem, "");
  EXPECT_EQ(log.partial, "");
  std::string phases;
  for (const auto& line : log.lines)
    if (line.find(R"("event":"engine")") != std::string::npos)
      phases += nlohmann::json::parse(line).value("phase", "") + " ";
  EXPECT_EQ(phases, "load started stopping stopped ") << last.out;
  EXPECT_EQ(notInLog(linesOf(tee.text()), log.lines), "");
  EXPECT_EQ(linesOf(tee.text()).size(), log.lines.size()) << "a reader that keeps up misses nothing";
  EXPECT_EQ(leftRunningAfter(c.dir, 5s), "");
  EXPECT_EQ(c.newInShm(shm_before), "");

  std::cout << fmt::format(
      "kills: {} in {:.1f} s (seed {}): {} before the engine started ({} runs held until they started), {} runs "
      "ended by themselves; {} log lines ({} logs ending in a partial line), {} of them seen on the tee\n",
      done, took_s, seed, before_started, held_to_start, ended_by_itself, c.lines_logged, c.partial_last_lines,
      c.lines_teed);
}

}  // namespace
}  // namespace keel::test
