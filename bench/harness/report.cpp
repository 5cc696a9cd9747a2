#include "report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace keel::bench {
namespace {

/// The paper's Table 3, Linux-Pentium4: recovery without (and with) preloading, per load level.
std::string paperCell(int load) {
  static const std::map<int, std::string> paper{{10, "20 ms (< 1 ms)"},
                                                {40, "2–12 ms (< 1 ms)"},
                                                {60, "10–30 ms (< 1 ms)"},
                                                {80, "> 100 ms (< 20 ms)"}};
  const auto it = paper.find(load);
  return it == paper.end() ? "—" : it->second;
}

const Row* find(const std::vector<Row>& rows, int load, const std::string& policy, const std::string& what) {
  for (const auto& r : rows)
    if (r.load == load && r.policy == policy && r.what == what) return &r;
  return nullptr;
}

std::string cell(const Row* r) {
  if (r == nullptr) return "";
  if (r->skipped || r->s.n == 0) return "skipped";
  return fmt::format("{:.1f} / {:.1f}", r->s.p50_us, r->s.p99_us);
}

/// keel ÷ a reference at p50 and p99, as printed ("—" when either is missing or zero).
std::string ratio(const Summary& keel, const Summary& ref) {
  if (keel.n == 0 || ref.n == 0 || ref.p50_us <= 0 || ref.p99_us <= 0) return "—";
  return fmt::format("{:.3g} / {:.3g}", keel.p50_us / ref.p50_us, keel.p99_us / ref.p99_us);
}

std::string ratio(const Row* keel, const Row* peer) { return keel && peer ? ratio(keel->s, peer->s) : "—"; }

/// keel ÷ a reference at p50 and p99, as written in the JSON (3 decimals).
/// `v` to three significant digits: a ratio far below 1 (keel beside a respawned process) keeps
/// its figures instead of rounding to 0.
double significant(double v) {
  if (v == 0 || !std::isfinite(v)) return v;
  const double scale = std::pow(10.0, 2 - std::floor(std::log10(std::fabs(v))));
  return std::round(v * scale) / scale;
}

nlohmann::json ratioJson(double keel_p50, double keel_p99, double ref_p50, double ref_p99) {
  return {{"p50", significant(keel_p50 / ref_p50)}, {"p99", significant(keel_p99 / ref_p99)}};
}

bool isPeer(const std::string& what) { return what.rfind("peer_", 0) == 0; }
bool isKeel(const std::string& what) { return !isPeer(what) && what.rfind("floor_", 0) != 0; }

}  // namespace

void addNote(std::string& notes, const std::string& note) {
  if (note.empty() || notes.find(note) != std::string::npos) return;
  notes += (notes.empty() ? "" : "; ") + note;
}

nlohmann::json toJson(const Row& r, bool detection) {
  nlohmann::json j;
  j["load"] = r.load;
  j["load_achieved"] = std::round(r.load_achieved * 10) / 10;
  j["load_source"] = r.load_source;
  if (detection) {
    j["kind"] = r.what;
    j["detector"] = r.detector;
  } else {
    j["mechanism"] = r.what;
  }
  j["policy"] = r.policy;
  j["n"] = r.s.n;
  j["p50_us"] = std::round(r.s.p50_us * 100) / 100;
  j["p99_us"] = std::round(r.s.p99_us * 100) / 100;
  j["max_us"] = std::round(r.s.max_us * 100) / 100;
  j["failed"] = r.failed;
  if (r.floor.n > 0 && r.floor.p50_us > 0 && r.floor.p99_us > 0) {
    j["floor_p50_us"] = std::round(r.floor.p50_us * 100) / 100;
    j["floor_p99_us"] = std::round(r.floor.p99_us * 100) / 100;
    j["vs_floor"] = ratioJson(r.s.p50_us, r.s.p99_us, r.floor.p50_us, r.floor.p99_us);
  }
  if (r.skipped) j["skipped"] = true;
  if (!r.note.empty()) j["note"] = r.note;
  return j;
}

void addPeerRatios(nlohmann::json& rows) {
  for (auto& k : rows) {
    if (!k.contains("mechanism") || !isKeel(k["mechanism"]) || k["n"] == 0) continue;
    for (const auto& p : rows) {
      if (!p.contains("mechanism") || !isPeer(p["mechanism"]) || p["n"] == 0) continue;
      if (p["load"] != k["load"] || p["policy"] != k["policy"]) continue;
      const double p50 = p["p50_us"], p99 = p["p99_us"];
      if (p50 <= 0 || p99 <= 0) continue;
      k["vs_" + p["mechanism"].get<std::string>()] = ratioJson(k["p50_us"], k["p99_us"], p50, p99);
    }
  }
}

void printFloorRatios(const std::vector<Row>& rows, std::ostream& out) {
  std::vector<std::string> kinds;
  std::vector<std::pair<int, std::string>> cells;  // load, policy, in the order measured
  for (const auto& r : rows) {
    if (r.floor.n > 0 && std::find(kinds.begin(), kinds.end(), r.what) == kinds.end()) kinds.push_back(r.what);
    if (std::find(cells.begin(), cells.end(), std::pair{r.load, r.policy}) == cells.end())
      cells.emplace_back(r.load, r.policy);
  }
  if (kinds.empty()) return;
  out << "\nkeel ÷ the machine's floor for the same fault, measured interleaved in the same cell, p50 / p99 "
         "(1: keel adds nothing)\n\n| load | policy |";
  for (const auto& k : kinds) out << ' ' << k << " |";
  out << "\n|---|---|";
  for (std::size_t i = 0; i < kinds.size(); ++i) out << "---|";
  out << '\n';
  for (const auto& [load, policy] : cells) {
    out << fmt::format("| {}% | {} |", load, policy);
    for (const auto& k : kinds) {
      const Row* r = find(rows, load, policy, k);
      out << ' ' << (r ? ratio(r->s, r->floor) : "—") << " |";
    }
    out << '\n';
  }
}

void printCells(const std::vector<Row>& rows, bool detection, std::ostream& out) {
  out << (detection ? "| load | achieved | kind | detector | policy | n | p50 µs | p99 µs | max µs | failed | note |\n"
                      "|---|---|---|---|---|---|---|---|---|---|---|\n"
                    : "| load | achieved | mechanism | policy | n | p50 µs | p99 µs | max µs | failed | note |\n"
                      "|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& r : rows) {
    const std::string head = detection ? fmt::format("{} | {}", r.what, r.detector) : r.what;
    if (r.skipped) {
      out << fmt::format("| {}% | {:.0f}% ({}) | {} | {} | — | — | — | — | — | skipped: {} |\n", r.load,
                         r.load_achieved, r.load_source, head, r.policy, r.note);
      continue;
    }
    out << fmt::format("| {}% | {:.0f}% ({}) | {} | {} | {} | {:.1f} | {:.1f} | {:.1f} | {} | {} |\n", r.load,
                       r.load_achieved, r.load_source, head, r.policy, r.s.n, r.s.p50_us, r.s.p99_us, r.s.max_us,
                       r.failed, r.note);
  }
}

void printTable3(const std::vector<Row>& rows, std::ostream& out) {
  std::vector<std::string> whats;
  std::set<int> loads;
  std::vector<std::string> policies;
  for (const auto& r : rows) {
    if (std::find(whats.begin(), whats.end(), r.what) == whats.end()) whats.push_back(r.what);
    if (std::find(policies.begin(), policies.end(), r.policy) == policies.end()) policies.push_back(r.policy);
    loads.insert(r.load);
  }
  std::vector<std::string> peers, keel;
  for (const auto& w : whats) {
    if (isPeer(w)) peers.push_back(w);
    if (isKeel(w)) keel.push_back(w);
  }
  for (const auto& policy : policies) {
    out << fmt::format("\nRecovery time, p50 / p99 µs, SCHED_{} (the paper's Table 3: without (with) preloading)\n\n",
                       policy == "fifo" ? "FIFO" : "OTHER");
    out << "| load (achieved) |";
    for (const auto& w : whats) out << ' ' << w << " |";
    out << " paper, Linux-Pentium4 |\n|---|";
    for (std::size_t i = 0; i <= whats.size(); ++i) out << "---|";
    out << '\n';
    for (int load : loads) {
      const Row* any = nullptr;
      for (const auto& w : whats)
        if ((any = find(rows, load, policy, w))) break;
      if (!any) continue;
      out << fmt::format("| ~{}% ({:.0f}%) |", load, any->load_achieved);
      for (const auto& w : whats) out << ' ' << cell(find(rows, load, policy, w)) << " |";
      out << ' ' << paperCell(load) << " |\n";
    }
    std::vector<std::pair<std::string, std::string>> opros;  // (OPRoS victim, the same with a keel one)
    for (const auto& w : keel)
      if (w.ends_with("_opros") && std::find(keel.begin(), keel.end(), w.substr(0, w.size() - 6)) != keel.end())
        opros.emplace_back(w, w.substr(0, w.size() - 6));
    if (!opros.empty()) {
      out << "\nA victim written against the OPRoS API ÷ the same written against keel's, p50 / p99 (1: the same)"
             "\n\n| load |";
      for (const auto& [o, k] : opros) out << ' ' << o << " ÷ " << k << " |";
      out << "\n|---|";
      for (std::size_t i = 0; i < opros.size(); ++i) out << "---|";
      out << '\n';
      for (int load : loads) {
        out << fmt::format("| ~{}% |", load);
        for (const auto& [o, k] : opros)
          out << ' ' << ratio(find(rows, load, policy, o), find(rows, load, policy, k)) << " |";
        out << '\n';
      }
    }
    if (peers.empty() || keel.empty()) continue;
    out << "\nkeel ÷ peer, p50 / p99 (below 1: keel recovers faster)\n\n| load |";
    for (const auto& k : keel)
      for (const auto& p : peers) out << ' ' << k << " ÷ " << p << " |";
    out << "\n|---|";
    for (std::size_t i = 0; i < keel.size() * peers.size(); ++i) out << "---|";
    out << '\n';
    for (int load : loads) {
      out << fmt::format("| ~{}% |", load);
      for (const auto& k : keel)
        for (const auto& p : peers)
          out << ' ' << ratio(find(rows, load, policy, k), find(rows, load, policy, p)) << " |";
      out << '\n';
    }
  }
}

void printIsolation(const std::vector<Row>& rows, std::ostream& out) {
  std::set<std::pair<int, std::string>> cells;
  for (const auto& r : rows) cells.insert({r.load, r.policy});
  auto floorCell = [](const Row* r) {
    return r && r->floor.n > 0 ? fmt::format("{:.1f} / {:.1f}", r->floor.p50_us, r->floor.p99_us) : std::string("—");
  };
  out << "\nPorts, one way (p50 / p99 µs): push → the reading component runs with the sample\n\n"
      << "| load | policy | keel, across processes | floor: a process wakes another | keel, in one process | "
         "CycloneDDS loopback | DDS ÷ keel across |\n|---|---|---|---|---|---|---|\n";
  for (const auto& [load, policy] : cells) {
    const Row* across = find(rows, load, policy, "port_process");
    const Row* dds = find(rows, load, policy, "port_dds");
    if (!across && !dds && !find(rows, load, policy, "port_thread")) continue;
    out << fmt::format("| {}% | {} | {} | {} | {} | {} | {} |\n", load, policy, cell(across), floorCell(across),
                       cell(find(rows, load, policy, "port_thread")), cell(dds), ratio(dds, across));
  }
  out << "\nTakeover (p50 / p99 µs): kill -9 of the active process → the first step of the process that runs "
         "the component next\n\n"
      << "| load | policy | keel, standby takes over | floor: robust futex wake on death, as many threads | "
         "takeover ÷ floor | floor, 1 thread | keel, cold respawn | respawn ÷ takeover |\n"
         "|---|---|---|---|---|---|---|---|\n";
  for (const auto& [load, policy] : cells) {
    const Row* take = find(rows, load, policy, "takeover");
    const Row* respawn = find(rows, load, policy, "respawn");
    if (!take && !respawn) continue;
    out << fmt::format("| {}% | {} | {} | {} | {} | {} | {} | {} |\n", load, policy, cell(take), floorCell(take),
                       take ? ratio(take->s, take->floor) : "—", cell(find(rows, load, policy, "floor_robust")),
                       cell(respawn), ratio(respawn, take));
  }
}

void printDds(const std::vector<Row>& rows, int deadline_ms, int lease_ms, std::ostream& out) {
  std::set<int> loads;
  for (const auto& r : rows) loads.insert(r.load);
  auto ms = [](const Row* r) {
    return r && r->s.n > 0
               ? fmt::format("{:.1f} / {:.1f} / {:.1f}", r->s.p50_us / 1000, r->s.p99_us / 1000, r->s.max_us / 1000)
               : std::string("—");
  };
  out << "\nRound trip over DDS (p50 / p99 µs): a stamp out on one topic, echoed back on another, 1 kHz, "
         "std_msgs/msg/Header, reliable\n\n"
      << "| load | keel ↔ keel | CycloneDDS C program | keel ÷ CycloneDDS (goal ≤ 1.1) | rclpy ↔ rclpy |\n"
         "|---|---|---|---|---|\n";
  for (int load : loads) {
    const Row* keel = find(rows, load, "other", "roundtrip_keel");
    const Row* raw = find(rows, load, "other", "roundtrip_raw");
    out << fmt::format("| {}% | {} | {} | {} | {} |\n", load, cell(keel), cell(raw), ratio(keel, raw),
                       cell(find(rows, load, "other", "roundtrip_rclpy")));
  }
  out << fmt::format(
      "\nFaults from the network (p50 / p99 / max ms), from the kill -9\n\n"
      "| load | `remote` detected, deadline {} ms (goal p99 ≤ {} ms) | failover across hosts, lease {} ms "
      "(goal p99 ≤ {} ms) |\n|---|---|---|\n",
      deadline_ms, deadline_ms + 10, lease_ms, lease_ms + 10);
  for (int load : loads)
    out << fmt::format("| {}% | {} | {} |\n", load, ms(find(rows, load, "other", "remote")),
                       ms(find(rows, load, "other", "failover")));
}

}  // namespace keel::bench
