// keel report as a user runs it: the summary keel run printed, read again from the run's fault
// log and from its recording, whole or cut by a kill -9; bad input refused with where and why;
// --plots drawing the fault timeline. One recorded run of the fault-detection example serves all.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "support/env.hpp"
#include "support/paths.hpp"
#include "support/process.hpp"

namespace keel {
namespace {

namespace fs = std::filesystem;

class Report : public ::testing::Test {
 protected:
  // Recorded once: the run takes 2 s.
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("keel_report_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    const std::string app = std::string(KEEL_EXAMPLES) + "/02_fault_detection";
    run_ = test::runProcess({KEEL_CLI, "run", app + "/app.xml", "--inject", app + "/scenario.xml", "--duration", "2",
                             "--log", path("run.jsonl"), "--record", path("run.mcap")});
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  void SetUp() override { ASSERT_EQ(run_.status, 0) << run_.err; }

  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static test::Ran report(std::vector<std::string> args) {
    args.insert(args.begin(), {KEEL_CLI, "report"});
    return test::runProcess(args);
  }
  /// A copy of the recording with only its first `size` bytes, as a kill -9 leaves it.
  static std::string cutRecording(std::uintmax_t size) {
    std::string cut = path("cut_" + std::to_string(size) + ".mcap");
    fs::copy_file(path("run.mcap"), cut, fs::copy_options::overwrite_existing);
    fs::resize_file(cut, size);
    return cut;
  }
  static std::string write(const std::string& name, const std::string& text) {
    std::ofstream(path(name)) << text;
    return path(name);
  }

  static inline fs::path dir_;
  static inline test::Ran run_;
};

TEST_F(Report, PrintsTheSummaryKeelRunPrintedFromTheLogAndFromTheRecording) {
  // The run must have had faults to report, or equal summaries would prove little.
  ASSERT_NE(run_.out.find("faults:"), std::string::npos) << run_.out;
  ASSERT_NE(run_.out.find("sonar_right"), std::string::npos) << run_.out;
  ASSERT_NE(run_.out.find("avoider"), std::string::npos) << run_.out;
  for (const char* file : {"run.jsonl", "run.mcap"}) {
    const auto r = report({path(file)});
    EXPECT_EQ(r.status, 0) << file << '\n' << r.err;
    EXPECT_EQ(r.out, run_.out) << file;
    EXPECT_EQ(r.err, "") << file;
  }
}

// Cut in its summary section, the recording still has every record: the same summary, after
// the line saying it was cut. Cut in its data, it has what came before.
TEST_F(Report, ACutRecordingIsReportedUpToTheCutAndSaysSo) {
  const auto size = fs::file_size(path("run.mcap"));
  const auto whole = report({cutRecording(size - 40)});
  EXPECT_EQ(whole.status, 0) << whole.err;
  const auto first = whole.out.substr(0, whole.out.find('\n') + 1);
  EXPECT_TRUE(first.starts_with("recording cut short (kill -9?): ")) << whole.out;
  EXPECT_NE(first.find("the summary covers the run up to 2."), std::string::npos) << first;
  EXPECT_EQ(whole.out.substr(first.size()), run_.out);

  // Where the chunks end depends on the run's timing (one at least a second): of cuts at every
  // tenth, each reports the chunks before it, or says there are none; some report part of the run.
  int partial = 0;
  for (int tenths = 1; tenths <= 9; ++tenths) {
    const auto r = report({cutRecording(size * tenths / 10)});
    if (r.status == 2) {
      EXPECT_NE(r.err.find("a recording cut before its first whole chunk (kill -9?)"), std::string::npos) << r.err;
      continue;
    }
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(r.out.starts_with("recording cut short (kill -9?): ")) << r.out;
    EXPECT_NE(r.out.find("keel: 'fault_detection'"), std::string::npos) << r.out;
    partial += r.out.find("(stopped: duration)") == std::string::npos;  // the stopping record is lost
  }
  EXPECT_GT(partial, 0);

  const auto magic = report({cutRecording(4)});  // killed while writing the magic
  EXPECT_EQ(magic.status, 2) << magic.out;
  EXPECT_NE(magic.err.find("inside the magic"), std::string::npos) << magic.err;
}

TEST_F(Report, BadInputExitsTwoSayingWhereAndWhy) {
  std::string log = test::slurp(path("run.jsonl"));
  const auto third = log.find('\n', log.find('\n') + 1) + 1;
  log.insert(third, "{\"event\": \n");  // line 3
  const std::vector<std::pair<std::string, std::string>> cases = {
      {path("missing.jsonl"), path("missing.jsonl") + ": cannot open: No such file or directory"},
      {write("empty.jsonl", ""), path("empty.jsonl") + ": an empty file"},
      {write("torn.jsonl", log), path("torn.jsonl") + ":3: not JSON"},
      {write("text.txt", "hello\n"), path("text.txt") + ":1: not JSON: neither a fault log"},
      {write("other.jsonl", "{\"a\": 1}\n"), path("other.jsonl") + ":1: not a fault-log record"},
      {dir_.string(), dir_.string() + ": a directory"},
  };
  for (const auto& [file, why] : cases) {
    const auto r = report({file});
    EXPECT_EQ(r.status, 2) << file << '\n' << r.out << r.err;
    EXPECT_EQ(r.out, "") << file;
    EXPECT_NE(r.err.find("keel report: " + why), std::string::npos) << r.err;
  }
}

// A run killed while writing its log's last line leaves it torn: reported, as keel run would.
TEST_F(Report, AFaultLogWhoseLastLineIsTornIsReported) {
  std::string log = test::slurp(path("run.jsonl"));
  log += R"({"event":"detected","t_ns":12)";
  const auto r = report({write("cut.jsonl", log)});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("1 line(s) of the log are not JSON records"), std::string::npos) << r.out;
}

bool haveMatplotlib() { return test::runProcess({"/usr/bin/python3", "-c", "import matplotlib"}).status == 0; }

TEST_F(Report, PlotsDrawTheFaultTimeline) {
  if (!haveMatplotlib()) GTEST_SKIP() << "no matplotlib for /usr/bin/python3 (scripts/deps.sh installs it)";
  const auto r = report({path("run.mcap"), "--plots", path("plots")});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out.starts_with(run_.out)) << r.out;
  EXPECT_NE(r.out.find(path("plots") + "/timeline.svg"), std::string::npos) << r.out;
  const std::string svg = test::slurp(path("plots") + "/timeline.svg");
  for (const char* text : {"sonar_right", "avoider", "detected after", "recovered after"})
    EXPECT_NE(svg.find(text), std::string::npos) << text;
  // Not the robot: no Fig. 6 nor trajectory, and nothing said about them.
  EXPECT_FALSE(fs::exists(path("plots") + "/fig6.svg"));
  EXPECT_EQ(r.err, "");
}

TEST_F(Report, PlotsWithoutPythonSaySoWithoutATraceback) {
  test::Ran r;
  {
    const test::ScopedEnv no_python("PATH", "/nonexistent");
    r = report({path("run.jsonl"), "--plots", path("no_python")});
  }
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(r.out.starts_with(run_.out)) << r.out;  // the summary first
  EXPECT_NE(r.err.find("--plots needs python3 with matplotlib, and there is no python3 on PATH"), std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace keel
