// The peers of `keel bench recovery` (peers.hpp), run as child processes of the harness.
//   erlang   erlc compiles share/keel/bench/peers/*.erl into a temporary directory; `erl` runs
//            keel_bench_sup:main(N), which times each restart itself (T1 - T0 on the VM's
//            monotonic clock) and prints `latency <ns>` lines, `failed <k>` and `done`
//   respawn  a thread of the harness is the supervisor: it posix_spawns keel-bench-child, tells
//            it to crash, reaps it (pidfd) and spawns it again at once; latency = the new
//            child's "ready" time - the old one's "crash" time (CLOCK_MONOTONIC, both children's)
// Both pace faults as keel's own trials do (10 ms before the first, 3 ms between) and begin with
// one uncounted warm-up fault. fifo: the peer's processes (and the respawn supervisor's thread,
// for that run only) run under SCHED_FIFO 50, Erlang without its schedulers' busy wait. Every
// step of a fault is bounded (2 s); every process spawned is reaped and every descriptor closed
// on every path. Each call is self-contained: safe to call from any thread.
#include "peers.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string_view>
#include <system_error>
#include <thread>

#include "process.hpp"

namespace fs = std::filesystem;

namespace keel::bench {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr auto kStepBound = 2s;  // each step of a fault: crash report, death, ready report

PeerResult skip(std::string why) {
  PeerResult r;
  r.skipped = std::move(why);
  return r;
}

/// The integer after `prefix` in `line` ("latency 123"), or nullopt.
std::optional<std::int64_t> field(std::string_view line, std::string_view prefix) {
  if (!line.starts_with(prefix)) return std::nullopt;
  std::int64_t value = 0;
  const char* end = line.data() + line.size();
  const auto [ptr, ec] = std::from_chars(line.data() + prefix.size(), end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

// --- erlang ------------------------------------------------------------------------------------

/// The last few lines of a command's output, for a reason to show.
std::string lastLines(const std::vector<std::string>& lines) {
  std::string out;
  const std::size_t from = lines.size() > 5 ? lines.size() - 5 : 0;
  for (std::size_t i = from; i < lines.size(); ++i) out += (out.empty() ? "" : " | ") + lines[i];
  return out.empty() ? "no output" : out;
}

/// Reads erl's report (see keel_bench_sup.erl) into `result`; false unless it is complete.
bool parseErlangReport(const std::vector<std::string>& lines, PeerResult& result) {
  bool done = false;
  for (const std::string& line : lines) {
    if (auto latency = field(line, "latency ")) result.latencies_ns.push_back(*latency);
    else if (auto failed = field(line, "failed ")) result.failed = static_cast<std::size_t>(*failed);
    else if (line.starts_with("otp ")) result.detail = "OTP " + line.substr(4);
    else if (line == "done") done = true;
  }
  return done;
}

/// erlc over every .erl in `sources` into `out`; empty, or why not.
std::string compileErlang(const std::string& erlc, const std::string& sources, const std::string& out) {
  std::vector<std::string> argv{erlc, "-o", out};
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(sources, ec))
    if (entry.path().extension() == ".erl") argv.push_back(entry.path().string());
  if (argv.size() == 3) return "no Erlang peer sources in " + sources;
  const Captured built = runCaptured(argv, false, Clock::now() + 120s);
  if (!built.error.empty()) return "erlc: " + built.error;
  if (built.status != 0) return "erlc failed: " + lastLines(built.lines);
  return {};
}

}  // namespace

PeerResult runErlangPeer(const Paths& paths, int n, bool fifo) {
  const std::string erl = findInPath("erl"), erlc = findInPath("erlc");
  if (erl.empty() || erlc.empty()) return skip("erl not found (scripts/deps.sh installs erlang-base)");
  const TempDir dir("keel-bench-erl-");
  if (dir.path().empty()) return skip(std::string("mkdtemp: ") + std::generic_category().message(errno));
  if (std::string error = compileErlang(erlc, paths.peers, dir.path()); !error.empty()) return skip(error);

  n = std::max(n, 0);
  std::vector<std::string> argv{
      erl, "-noshell", "-noinput", "-pa", dir.path(), "-eval", "keel_bench_sup:main(" + std::to_string(n) + ")."};
  // Under SCHED_FIFO the schedulers' busy wait (the VM spins a while before sleeping) would
  // starve every SCHED_OTHER process on the machine, the load and the harness included; an
  // Erlang node run at real-time priority turns it off, and so do we.
  if (fifo) argv.insert(argv.begin() + 1, {"+sbwt", "none", "+sbwtdcpu", "none", "+sbwtdio", "none"});
  // Inside, each step of a fault is bounded by 2 s; this bounds the whole run.
  const Captured ran = runCaptured(argv, fifo, Clock::now() + 60s + (n + 1) * 2 * kStepBound);
  if (!ran.error.empty()) return skip("erl: " + ran.error);
  PeerResult result;
  if (!parseErlangReport(ran.lines, result) || ran.status != 0)
    return skip("erl did not complete (status " + std::to_string(ran.status) + "): " + lastLines(ran.lines));
  return result;
}

// --- respawn -----------------------------------------------------------------------------------

namespace {

/// The supervisor of keel-bench-child: one child at a time, driven by the calling thread.
class Respawner {
 public:
  Respawner(std::string child, bool fifo) : child_(std::move(child)), fifo_(fifo) {}

  /// A fresh child (and fresh pipes) that has reported ready; empty, or why not.
  std::string restart() {
    proc_.reset();
    if (!command_.open() || !report_.open()) return std::string("pipe: ") + std::generic_category().message(errno);
    reader_ = LineReader(report_.read.get());
    if (std::string error = spawnChild(); !error.empty()) return error;
    if (!expect("ready ")) return "keel-bench-child did not report ready within 2 s";
    return {};
  }

  /// One fault: crash, reap, respawn. The latency, or nullopt when a step passed its bound;
  /// `error` is set when the peer cannot go on.
  std::optional<std::int64_t> fault(std::string& error) {
    static constexpr std::string_view kCrash = "crash\n";
    if (write(command_.write.get(), kCrash.data(), kCrash.size()) != static_cast<ssize_t>(kCrash.size()))
      return std::nullopt;
    const auto crashed = expect("crash ");
    if (!crashed) return std::nullopt;
    const std::optional<int> status = proc_->waitUntil(Clock::now() + kStepBound);
    if (!status) return std::nullopt;
    if (!WIFSIGNALED(*status) || WTERMSIG(*status) != SIGSEGV) {
      error = "keel-bench-child did not die of SIGSEGV (wait status " + std::to_string(*status) + ")";
      return std::nullopt;
    }
    error = spawnChild();
    if (!error.empty()) return std::nullopt;
    const auto ready = expect("ready ");
    if (!ready) return std::nullopt;
    return *ready - *crashed;
  }

  /// End of file on its stdin: the child exits (or is killed past the bound) and is reaped.
  void stop() {
    command_.write.reset();
    if (proc_) proc_->waitUntil(Clock::now() + kStepBound);
    proc_.reset();
  }

 private:
  std::string spawnChild() {
    proc_.reset();
    auto spawned = Process::spawn({child_}, {.in = command_.read.get(), .out = report_.write.get()}, fifo_, false);
    if (!spawned) return "keel-bench-child: " + spawned.error().message;
    proc_.emplace(std::move(*spawned));
    return {};
  }

  /// The time in the child's next line if it is "<prefix><ns>", within the bound.
  std::optional<std::int64_t> expect(std::string_view prefix) {
    const std::optional<std::string> line = reader_.next(Clock::now() + kStepBound);
    return line ? field(*line, prefix) : std::nullopt;
  }

  std::string child_;
  bool fifo_;
  Pipe command_, report_;  // kept across respawns: each child gets the same two as stdin/stdout
  LineReader reader_{-1};
  std::optional<Process> proc_;  // declared last: killed and reaped before the pipes close
};

PeerResult superviseRespawns(const std::string& child, int n, bool fifo) {
  if (fifo)
    if (std::string why = becomeFifo(); !why.empty()) return skip(why);
  Respawner sup(child, fifo);
  std::string error = sup.restart();
  if (error.empty() && !sup.fault(error) && error.empty()) error = sup.restart();  // the warm-up
  if (!error.empty()) return skip(error);
  std::this_thread::sleep_for(10ms);
  PeerResult result;
  for (int i = 0; i < n; ++i) {
    if (auto latency = sup.fault(error)) {
      result.latencies_ns.push_back(*latency);
      std::this_thread::sleep_for(3ms);
      continue;
    }
    if (error.empty()) {
      ++result.failed;
      error = sup.restart();
    }
    if (!error.empty()) return skip(error);
  }
  sup.stop();
  return result;
}

}  // namespace

PeerResult runRespawnPeer(const Paths& paths, int n, bool fifo) {
  if (access(paths.child.c_str(), X_OK) != 0) return skip("keel-bench-child not found at " + paths.child);
  // A thread of its own, so that SCHED_FIFO ends with it and never sticks to the caller.
  PeerResult result;
  try {
    std::thread supervisor([&] { result = superviseRespawns(paths.child, n, fifo); });
    supervisor.join();
  } catch (const std::system_error& e) {
    return skip(std::string("supervising thread: ") + e.what());
  }
  return result;
}

}  // namespace keel::bench
