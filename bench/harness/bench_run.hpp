// A `keel run` as a user runs it, for the benchmarks that measure keel across processes
// (`keel bench isolation`, `keel bench dds`): profiles written for it into a directory of its
// own, the page its components share with the harness (bench_page.hpp), its fault log, and
// keel run started on them; stopped with SIGTERM as an operator stops it, killed and reaped
// on every other path.
#pragma once

#include <signal.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_page.hpp"
#include "paths.hpp"
#include "process.hpp"

namespace keel::bench {

/// One component profile of a benchmark library, its `page` property set.
std::string benchComponentXml(const std::string& library, const std::string& name, const std::string& semantics,
                              const std::string& ports, const std::string& page, const std::string& properties = "");

/// `<priority>` and `<policy>` of a component under SCHED_FIFO kFifoPriority; empty otherwise.
std::string schedXml(bool fifo);

/// A page (bench_page.hpp) on tmpfs, created, sized and mapped; removed when this goes.
class SharedPage {
 public:
  SharedPage();
  ~SharedPage();
  SharedPage(const SharedPage&) = delete;
  SharedPage& operator=(const SharedPage&) = delete;
  /// Creates it afresh (zeroed); empty, or why not.
  std::string create();
  const std::string& path() const { return path_; }
  keel_bench::BenchPage& operator*() const { return *page_; }

 private:
  static inline int counter_ = 0;
  std::string path_;
  keel_bench::BenchPage* page_ = nullptr;
};

/// The records a fault log gains, read as it is written (whole lines only).
class LogTail {
 public:
  explicit LogTail(std::string path = {}) : path_(std::move(path)) {}
  void reset(std::string path) {
    path_ = std::move(path);
    read_ = 0;
  }
  /// The records written since the last call.
  std::vector<nlohmann::json> newRecords();

 private:
  std::string path_;
  std::size_t read_ = 0;
};

class BenchRun {
 public:
  explicit BenchRun(const Paths& paths, const std::string& prefix = "keel-bench-");
  ~BenchRun();
  BenchRun(const BenchRun&) = delete;
  BenchRun& operator=(const BenchRun&) = delete;

  const std::string& pagePath() const { return page_.path(); }
  keel_bench::BenchPage& page() { return *page_; }
  pid_t pid() const { return proc_ ? proc_->pid() : -1; }

  /// Writes `files` (name → text) beside each other, maps a fresh page and starts keel run on
  /// `package`, its argv after `launcher` when one is given (`ip netns exec NS`: it execs keel
  /// run, whose pid stays the one started), its environment the harness's with `env`'s changes
  /// and KEEL_COMPONENT_PATH set to the benchmark's components; empty, or why not.
  std::string start(const std::vector<std::pair<std::string, std::string>>& files, const std::string& package,
                    const std::vector<std::string>& launcher = {}, std::vector<EnvChange> env = {});

  /// Why keel run is not running as it should: its last lines.
  std::string failure(const std::string& what) const;

  /// The fault log's records written since the last call (whole lines only).
  std::vector<nlohmann::json> newRecords() { return log_.newRecords(); }

  /// Host records of `phase` seen so far (every call reads the new part of the log).
  std::size_t hostPhases(const std::string& phase);
  /// Each `recovered` record's recovered − detected so far: for a process fault, from the first to
  /// see the death (the standby waking, or keel run) to the first good step.
  const std::vector<std::int64_t>& recoveredNs() const { return recovered_ns_; }

  /// Sends `sig` to keel run and its component processes (its process group): SIGKILL is a
  /// host lost.
  void signal(int sig) const;
  /// SIGTERM, as an operator stops it: keel run stops its processes and ends.
  void stop();

 private:
  const Paths& paths_;
  TempDir dir_;
  SharedPage page_;
  std::string out_path_;
  LogTail log_;
  std::optional<Process> proc_;
  std::map<std::string, std::size_t> phases_;
  std::vector<std::int64_t> recovered_ns_;
};

}  // namespace keel::bench
