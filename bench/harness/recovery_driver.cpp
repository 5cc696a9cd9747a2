// keel bench recovery: its cells and its tables (driver.hpp).
#include <fmt/format.h>

#include <iostream>
#include <string>

#include "floor.hpp"
#include "peers.hpp"
#include "process_floor.hpp"
#include "recovery.hpp"

#include "driver.hpp"

namespace keel::bench {

void recoveryCell(const Paths& paths, int n, const std::string& log, const std::string& what, bool fifo, Row& row) {
  if (what == "floor_wake" || what == "floor_timer") {
    FloorResult f = what == "floor_wake" ? measureWakeFloor(n, fifo) : measureTimerFloor(n, fifo);
    row.s = summarise(std::move(f.latencies_ns));
    addNote(row.note, f.warnings);
    return;
  }
  if (what == "peer_erlang" || what == "peer_respawn") {
    PeerResult p = what == "peer_erlang" ? runErlangPeer(paths, n, fifo) : runRespawnPeer(paths, n, fifo);
    row.skipped = !p.skipped.empty();
    row.note = p.skipped;
    row.s = summarise(std::move(p.latencies_ns));
    row.failed = p.failed;
    return;
  }
  RecoveryCell c = measureRecovery(paths, what, fifo, n, log);
  if (!c.error.empty()) {
    row.skipped = true;
    row.note = c.error;
    return;
  }
  row.s = summarise(std::move(c.latencies_ns));
  row.failed = c.failed;
  if (c.unexpected) addNote(row.note, fmt::format("{} handled otherwise", c.unexpected));
  if (c.already_mapped) addNote(row.note, fmt::format("{} with the library already mapped", c.already_mapped));
  if (!c.to_client_ns.empty()) {
    const Summary to = summarise(std::move(c.to_client_ns));
    addNote(row.note,
            fmt::format("detection to a monitor client {:.0f} / {:.0f} µs (n {})", to.p50_us, to.p99_us, to.n));
  }
  if (!c.in_place_ns.empty()) {
    const Summary in = summarise(std::move(c.in_place_ns));
    addNote(row.note, fmt::format("in place {:.1f} / {:.1f} µs", in.p50_us, in.p99_us));
  }
  addNote(row.note, c.warnings);
}

int recoveryBenchmark(Options o, const Paths& paths) {
  if (o.which.empty())
    o.which = {"reset",       "replace_cold", "replace_preloaded", "reset_opros", "replace_preloaded_opros",
               "peer_erlang", "peer_respawn", "floor_wake",        "floor_timer"};
  const auto low = lowLatency(o.low_latency);
  header(o, "recovery");
  const std::string log = fmt::format("/tmp/keel-bench-recovery.{}.log", ::getpid());
  auto rows = runCells(o, paths, o.which,
                       [&](const std::string& w, bool fifo, Row& row) { recoveryCell(paths, o.n, log, w, fifo, row); });
  std::remove(log.c_str());
  printTable3(rows, std::cout);
  std::cout
      << "\nEvery cell (p50 / p99 / max over n faults; achieved: the machine's busy CPU time during the cell)\n\n";
  printCells(rows, false, std::cout);
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : rows) j.push_back(toJson(r, false));
  addPeerRatios(j);
  finish(o, paths, "recovery", j);
  return 0;
}

}  // namespace keel::bench
