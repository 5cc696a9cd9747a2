// keel soak [PROFILE] [--minutes M] [--fault-every MS] [--seed S] [--log FILE] [--warmup S]
//           [--round S] [--set I.P=V]...: a random fault campaign against an application
// (src/soak, docs/soak.md), the simulated robot by default. A progress line while it runs; at
// the end the faults injected per kind and what became of them, the log's lines, memory and
// descriptors, then each violation. Exit 0 without violations, 1 with (named), 2 when the
// application cannot be run at all.
#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>

#include "cli/commands.hpp"
#include "soak/campaign.hpp"

namespace keel::cli {
namespace {

/// The simulated robot's system profile: installed beside keel, or in the source tree keel
/// was built from.
std::string defaultProfile() {
  std::error_code ec;
  const auto self = std::filesystem::canonical("/proc/self/exe", ec);
  if (!ec) {
    const auto installed = self.parent_path().parent_path() / "share" / "keel" / "robot" / "system.xml";
    if (std::filesystem::exists(installed, ec)) return installed.string();
  }
  return KEEL_SOURCE_ROBOT "/system.xml";
}

std::string mb(std::uint64_t bytes) { return fmt::format("{:.1f} MB", static_cast<double>(bytes) / 1e6); }
std::string mb2(std::uint64_t bytes) { return fmt::format("{:.2f} MB", static_cast<double>(bytes) / 1e6); }

void printProgress(const soak::SoakProgress& p, bool tty) {
  const std::string line = fmt::format(
      "keel soak: {:.0f}/{:.0f} s, round {}, {} faults injected, {} handled, {} violation(s), rss {}, "
      "heap {}, {} fds",
      p.elapsed_s, p.total_s, p.round, p.armed, p.handled, p.violations, mb(p.usage.rss_bytes), mb(p.usage.heap_bytes),
      p.usage.fds);
  if (tty) {
    std::cerr << '\r' << line << "\x1b[K" << std::flush;
    return;
  }
  static double last = -1e9;  // a line every 30 s in a log
  if (p.elapsed_s - last < 30) return;
  last = p.elapsed_s;
  std::cerr << line << '\n';
}

void printResult(const soak::SoakOptions& o, const soak::SoakResult& r) {
  fmt::print("keel soak {}: {} round(s) in {:.0f} s, a fault every {:.0f} ms on average, seed {}\n", o.profile,
             r.rounds, r.seconds, o.fault_every_ms, o.seed);
  fmt::print("  {:<18} {:>8} {:>8} {:>15} {:>10}\n", "kind", "injected", "handled", "not manifested", "overtaken");
  soak::KindCounts total;
  for (const auto& [kind, k] : r.by_kind) {
    fmt::print("  {:<18} {:>8} {:>8} {:>15} {:>10}\n", kind, k.armed, k.handled, k.not_manifested, k.overtaken);
    total.armed += k.armed;
    total.handled += k.handled;
    total.not_manifested += k.not_manifested;
    total.overtaken += k.overtaken;
  }
  fmt::print("  {:<18} {:>8} {:>8} {:>15} {:>10}\n", "all", total.armed, total.handled, total.not_manifested,
             total.overtaken);
  fmt::print(
      "  faults detected (injected or their consequences): {}; emergency stops pressed by the soak: {}; "
      "emergency latches (each process latches its own): {}, reached: {}; collisions: {}\n",
      r.detected, r.operator_emergencies, r.emergencies, r.emergencies_reached, r.collisions);
  fmt::print("  log: {} lines, none torn or missing{}\n", r.lines, r.violations.empty() ? "" : " (see below)");
  if (r.baseline) {
    auto pct = [](double from, double to) { return from > 0 ? (to / from - 1) * 100 : 0.0; };
    fmt::print("  resident memory: {} after round 1, {} after the warm-up, {} at the end ({:+.1f} %)\n",
               mb(r.start.rss_bytes), mb(r.baseline->rss_bytes), mb(r.last.rss_bytes),
               pct(static_cast<double>(r.baseline->rss_bytes), static_cast<double>(r.last.rss_bytes)));
    fmt::print("  heap in use: {} after round 1, {} after the warm-up, {} at the end ({:+.1f} %){}\n",
               mb2(r.start.heap_bytes), mb2(r.baseline->heap_bytes), mb2(r.last.heap_bytes),
               pct(static_cast<double>(r.baseline->heap_bytes), static_cast<double>(r.last.heap_bytes)),
               soak::kUnderAsan ? " (judged instead of resident memory under ASan, whose own bookkeeping grows)" : "");
    fmt::print("  open descriptors: {} after round 1, {} after the warm-up, {} at the end ({:+.1f} %)\n", r.start.fds,
               r.baseline->fds, r.last.fds, pct(static_cast<double>(r.baseline->fds), static_cast<double>(r.last.fds)));
  } else {
    fmt::print(
        "  resident memory {} → {}, open descriptors {} → {} (not checked: the soak ended within its "
        "{:.0f} s warm-up)\n",
        mb(r.start.rss_bytes), mb(r.last.rss_bytes), r.start.fds, r.last.fds, o.warmup_s);
  }
  if (r.violations.empty()) {
    fmt::print("keel soak: ok, no violation\n");
    return;
  }
  for (const auto& v : r.violations) fmt::print("keel soak: violation: {}\n", v);
}

int soakProfile(soak::SoakOptions o) {
  if (o.profile.empty()) o.profile = defaultProfile();
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  auto result = soak::runSoak(o, [tty](const soak::SoakProgress& p) { printProgress(p, tty); });
  if (tty) std::cerr << '\n';
  if (!result) {
    std::cerr << "keel soak: " << result.error().message << '\n';
    return 2;
  }
  printResult(o, *result);
  return result->violations.empty() ? 0 : 1;
}

}  // namespace

void addSoakCommand(CLI::App& app, std::function<int()>& run) {
  auto opts = std::make_shared<soak::SoakOptions>();
  CLI::App* cmd = app.add_subcommand("soak", "Run an application under random faults and check nothing is lost");
  cmd->add_option("profile", opts->profile, "package_profile or system_profile XML (default: the simulated robot)");
  cmd->add_option("--minutes", opts->minutes, "how long (default 10)")->check(CLI::PositiveNumber);
  cmd->add_option("--fault-every", opts->fault_every_ms, "ms between faults on average (default 500)")
      ->check(CLI::Range(10.0, 3'600'000.0));
  cmd->add_option("--seed", opts->seed, "the random campaign's seed (default 1)");
  cmd->add_option("--log", opts->log, "write the fault log of every round (JSON lines) to this file");
  cmd->add_option("--warmup", opts->warmup_s,
                  "seconds after which memory and descriptors are the baseline (default 60)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--round", opts->round_s, "a run's longest duration in seconds, before the next starts (default 60)")
      ->check(CLI::Range(2.0, 86400.0));
  cmd->add_option("--set", opts->sets, "INSTANCE.PROPERTY=VALUE for every run, as keel run --set")
      ->allow_extra_args(false);
  cmd->callback([opts, &run] { run = [opts] { return soakProfile(*opts); }; });
}

}  // namespace keel::cli
