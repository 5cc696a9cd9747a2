// keel report FILE.mcap|FILE.jsonl [--plots DIR [--trace CSV]]: prints the summary `keel run`
// printed at the end of a run, from its fault log or from its recording (the /keel/faults
// channel is every record of the log, in order). A recording cut by a kill -9 is reported up to
// the cut, and the first line says so. With --plots it writes the run's records into DIR and
// runs the plotting script (robot/plot_run.py, installed in share/keel/robot) there: the fault
// timeline of any run; for the robot, Fig. 6 from its wheel ports and the trajectory from its
// referee's truth and world ports, or both from the referee's trace (docs/commands.md#keel-report).
// Bad input: `keel report: FILE:LINE: what` (or FILE: what), exit 2.
#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/summary.hpp"
#include "monitor/mcap_reader.hpp"

namespace keel::cli {
namespace {

namespace fs = std::filesystem;

struct ReportOptions {
  std::string file;
  std::string plots;  // DIR: "" draws none
  std::string trace;  // the referee's CSV, for the trajectory
};

/// A run as keel report reads it, from either kind of file.
struct RunRecords {
  std::vector<std::string> log;    // the fault log's records, one JSON object per line, in order
  std::vector<std::string> ports;  // {"port","t_ns","value"} per port value (recordings only)
  std::string cut;                 // a recording cut short: why, for the first line
};

constexpr std::string_view kMcapMagic = "\x89MCAP";  // enough to tell the two apart
constexpr std::string_view kFaultsTopic = "/keel/faults";
constexpr std::string_view kPortsPrefix = "/keel/ports/";

/// The fault log, line by line. Every line must be a record (a JSON object with an `event`),
/// except a last line without its newline: a run killed while writing it leaves one, and the
/// summary counts it as not JSON, as `keel run` would.
Result<RunRecords> readLog(const std::string& path, std::istream& in) {
  RunRecords run;
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    const auto r = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    const bool torn_last = in.eof();  // getline hit the end before a newline
    if (r.is_object() && r.contains("event") && r["event"].is_string()) {
      run.log.push_back(std::move(line));
      continue;
    }
    if (torn_last && !run.log.empty() && !r.is_object()) {
      run.log.push_back(std::move(line));  // counted by the summary, not an error
      continue;
    }
    const char* what = r.is_discarded() ? "not JSON" : "not a fault-log record (a JSON object with an \"event\")";
    return Error{fmt::format("{}:{}: {}: neither a fault log (JSON lines) nor an MCAP recording", path, n, what)};
  }
  if (in.bad()) return Error{fmt::format("{}: cannot read: {}", path, std::generic_category().message(errno))};
  if (run.log.empty()) return Error{path + ": no records: an empty fault log"};
  return run;
}

/// A port value as plot_run.py reads it: the channel's {"t_ns","value"} and the port's name.
std::string portLine(std::string_view topic, const std::string& payload) {
  auto v = nlohmann::json::parse(payload, nullptr, /*allow_exceptions=*/false);
  if (!v.is_object()) return {};
  v["port"] = std::string(topic.substr(kPortsPrefix.size()));
  return v.dump();
}

/// The t_ns of the last record in `log`, in seconds (0 without one).
double lastRecordS(const std::vector<std::string>& log) {
  for (auto it = log.rbegin(); it != log.rend(); ++it) {
    const auto r = nlohmann::json::parse(*it, nullptr, /*allow_exceptions=*/false);
    if (r.is_object() && r.contains("t_ns") && r["t_ns"].is_number()) return r["t_ns"].get<double>() / 1e9;
  }
  return 0;
}

/// The recording's /keel/faults messages (the log), and its port values for the plots.
Result<RunRecords> readRecording(const std::string& path) {
  auto file = monitor::readMcap(path);
  if (!file) return file.error();
  const auto faults = std::find_if(file->channels.begin(), file->channels.end(),
                                   [](const monitor::McapChannel& c) { return c.topic == kFaultsTopic; });
  if (faults == file->channels.end()) {
    if (file->complete || !file->messages.empty())
      return Error{path + ": an MCAP file without a /keel/faults channel: not recorded by keel run --record"};
    return Error{
        fmt::format("{}: a recording cut before its first whole chunk (kill -9?): {}", path, file->stopped_at)};
  }
  RunRecords run;
  for (const auto& m : file->messages) {
    const monitor::McapChannel* c = file->channel(m.channel);
    if (c == &*faults) run.log.push_back(m.payload);
    else if (c && c->topic.starts_with(kPortsPrefix))
      if (std::string line = portLine(c->topic, m.payload); !line.empty()) run.ports.push_back(std::move(line));
  }
  if (!file->complete) {
    run.cut = fmt::format("recording cut short (kill -9?): {}; the summary covers the run up to {:.3f} s",
                          file->stopped_at, lastRecordS(run.log));
  }
  return run;
}

/// Either kind of file, told apart by its first bytes (an MCAP file starts with its magic).
Result<RunRecords> readRun(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return Error{path + ": a directory, not a fault log or a recording"};
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{fmt::format("{}: cannot open: {}", path, std::generic_category().message(errno))};
  std::string head(kMcapMagic.size(), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (head.empty()) return Error{path + ": an empty file: neither a fault log (JSON lines) nor an MCAP recording"};
  if (kMcapMagic.starts_with(head)) return readRecording(path);
  in.clear();
  in.seekg(0);
  return readLog(path, in);
}

/// The plotting script: installed beside keel, or in the source tree keel was built from.
std::string plotScript() {
  std::error_code ec;
  const auto self = fs::canonical("/proc/self/exe", ec);
  if (!ec) {
    const auto installed = self.parent_path().parent_path() / "share" / "keel" / "robot" / "plot_run.py";
    if (fs::exists(installed, ec)) return installed.string();
  }
  return KEEL_SOURCE_ROBOT "/plot_run.py";
}

Result<void> writeLines(const fs::path& path, const std::vector<std::string>& lines) {
  std::ofstream out(path);
  for (const auto& line : lines) out << line << '\n';
  out.close();
  if (!out) return Error{fmt::format("cannot write {}: {}", path.string(), std::generic_category().message(errno))};
  return {};
}

/// Runs `python3 SCRIPT ARGS...`; its exit status, or 127 when there is no python3.
int runPython(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::cout.flush();  // its lines after ours
  const pid_t pid = ::fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// Writes the run's records into `dir` (faults.jsonl, ports.jsonl) and has plot_run.py draw
/// them there. A plot that cannot be drawn is said on stderr: 1 (the summary was printed).
int drawPlots(const ReportOptions& o, const RunRecords& run) {
  std::error_code ec;
  fs::create_directories(o.plots, ec);
  if (ec) {
    std::cerr << fmt::format("keel report: cannot create {}: {}\n", o.plots, ec.message());
    return 2;
  }
  const fs::path dir(o.plots);
  std::vector<std::string> args{"python3", plotScript(), "--log", (dir / "faults.jsonl").string(), "--out", o.plots};
  auto written = writeLines(dir / "faults.jsonl", run.log);
  if (written && !run.ports.empty()) {
    written = writeLines(dir / "ports.jsonl", run.ports);
    args.insert(args.end(), {"--ports", (dir / "ports.jsonl").string()});
  }
  if (!written) {
    std::cerr << "keel report: " << written.error().message << '\n';
    return 2;
  }
  if (!o.trace.empty()) args.insert(args.end(), {"--trace", o.trace});
  const int status = runPython(args);
  if (status == 127) {
    std::cerr << "keel report: --plots needs python3 with matplotlib, and there is no python3 on PATH "
                 "(scripts/deps.sh installs both)\n";
  }
  if (status == 0) return 0;
  std::cerr << "keel report: the plots were not all drawn (" << args[1] << " exited " << status << ")\n";
  return status == 2 ? 2 : 1;
}

int report(const ReportOptions& o) {
  auto run = readRun(o.file);
  if (!run) {
    std::cerr << "keel report: " << run.error().message << '\n';
    return 2;
  }
  if (!run->cut.empty()) fmt::print("{}\n", run->cut);
  std::string log;
  for (const auto& line : run->log) (log += line) += '\n';
  std::istringstream records(log);
  printSummary(std::cout, summarize(records));
  return o.plots.empty() ? 0 : drawPlots(o, *run);
}

}  // namespace

void addReportCommand(CLI::App& app, std::function<int()>& run) {
  auto opts = std::make_shared<ReportOptions>();
  CLI::App* cmd = app.add_subcommand("report", "Print a run's summary, and draw its plots, from its log or recording");
  cmd->add_option("file", opts->file, "the run's fault log (keel run --log, JSON lines) or recording (--record, MCAP)")
      ->required();
  CLI::Option* plots =
      cmd->add_option("--plots", opts->plots,
                      "DIR: draw the run's plots there as SVG (python3 and matplotlib): the fault timeline; for the "
                      "robot, Fig. 6 and the trajectory");
  cmd->add_option("--trace", opts->trace,
                  "CSV: the robot referee's trace (its `trace` property): Fig. 6 and the trajectory on "
                  "simulated time")
      ->needs(plots);
  cmd->callback([opts, &run] { run = [opts] { return report(*opts); }; });
}

}  // namespace keel::cli
