// One scenario per fault-handling behaviour (issue: fault handling): a package under
// tests/scenarios/handling/ runs with a fault scenario injected, and the test asserts the
// handling from the fault log (`detected`, `diagnosed`, `action`, `recovered`, `state`, sharing
// a fault_id), from the engine (the fault manager's handlings, stopped components and
// applications, the component in service under a name) and from what the test components of
// tests/integration/components/handling_components.cpp report through their probe: the count
// a reset restored, what a tap downstream received, the command an actuator held.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <thread>

#include "engine/engine.hpp"
#include "injection/scenario.hpp"
#include "log/schema.hpp"
#include "runtime/component_core.hpp"
#include "runtime/injection.hpp"
#include "support/log_reader.hpp"
#include "support/paths.hpp"
#include "support/temp_log.hpp"

namespace keel {
namespace {

namespace schema = log::schema;
namespace ev = schema::event;
namespace fd = schema::field;
using namespace std::chrono_literals;
using nlohmann::json;

std::string here(const std::string& f) { return std::string(KEEL_SCENARIOS) + "/handling/" + f; }

class Handling : public ::testing::Test {
 protected:
  void SetUp() override {
    // The engine loads this library by its profiles' library_name; holding it open here as
    // well keeps one copy (and its probe table) loaded for the whole test.
    const std::string lib = std::string(KEEL_TEST_COMPONENTS) + "/libkeel_test_components.so";
    lib_ = dlopen(lib.c_str(), RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(lib_, nullptr) << dlerror();
    probe_ = reinterpret_cast<ProbeFn>(dlsym(lib_, "keel_handling_probe"));
    auto clear = reinterpret_cast<void (*)()>(dlsym(lib_, "keel_handling_probe_clear"));
    ASSERT_NE(probe_, nullptr);
    ASSERT_NE(clear, nullptr);
    clear();
  }

  void TearDown() override {
    if (engine_) engine_->shutdown();
    engine_.reset();
    std::filesystem::remove(log_);
    if (lib_) dlclose(lib_);
  }

  /// Creates and starts the engine over `package` with `scenario` injected ("" for none).
  engine::Engine& start(const std::string& package, const std::string& scenario) {
    auto set = profile::load(here(package));
    EXPECT_TRUE(set) << (set ? "" : set.error().front().str());
    if (!set) throw std::runtime_error("profile not loaded");
    engine::EngineOptions eo;
    eo.log_path = log_;
    eo.search_path = {KEEL_TEST_COMPONENTS, KEEL_STOCK_COMPONENTS};
    eo.warn = [](const std::string&) {};
    if (!scenario.empty()) {
      auto sc = injection::loadScenario(here(scenario));
      EXPECT_TRUE(sc) << (sc ? "" : sc.error().front().str());
      if (!sc) throw std::runtime_error("scenario not loaded");
      eo.scenario = std::move(*sc);
    }
    auto engine = engine::Engine::create(std::move(*set), eo);
    EXPECT_TRUE(engine) << (engine ? "" : engine.error().message);
    if (!engine) throw std::runtime_error("engine not created");
    engine_ = std::move(*engine);
    auto started = engine_->start();
    EXPECT_TRUE(started) << (started ? "" : started.error().message);
    return *engine_;
  }

  /// Shuts the engine down (everything handled is logged) and reads the log.
  std::vector<json> finish() {
    engine_->shutdown();
    return test::readLog(log_);
  }

  /// What `instance` reported under `key`, if it did.
  std::optional<long> probe(const std::string& instance, const std::string& key) const {
    long v = 0;
    if (probe_(instance.c_str(), key.c_str(), &v)) return v;
    return std::nullopt;
  }
  long probeOr0(const std::string& instance, const std::string& key) const { return probe(instance, key).value_or(0); }

  std::uint64_t executions(const std::string& name) const {
    Component* c = engine_->find(name);
    return c ? runtime::coreOf(*c).executions.load() : 0;
  }

  /// Polls `done` until it holds or `bound` passes (generous: a loaded machine).
  static bool waitFor(const std::function<bool()>& done, std::chrono::milliseconds bound = 2500ms) {
    const auto until = std::chrono::steady_clock::now() + bound;
    while (!done()) {
      if (std::chrono::steady_clock::now() >= until) return false;
      std::this_thread::sleep_for(2ms);
    }
    return true;
  }

  /// `name` executes at least `n` more times from now.
  bool keepsExecuting(const std::string& name, std::uint64_t n = 10) const {
    const std::uint64_t from = executions(name);
    return waitFor([&] { return executions(name) >= from + n; });
  }

  std::vector<fault::Handling> handlingsOf(const std::string& component) const {
    std::vector<fault::Handling> out;
    for (const auto& h : engine_->faultManager().handlings())
      if (h.component == component) out.push_back(h);
    return out;
  }

  /// The handlings of `component`, once `n` of them are recovered.
  bool recovered(const std::string& component, std::size_t n = 1) const {
    std::size_t done = 0;
    for (const auto& h : handlingsOf(component)) done += h.recovered_ns != 0;
    return done >= n;
  }

  std::unique_ptr<engine::Engine> engine_;
  std::string log_ = test::tempPath("keel_handling");

 private:
  using ProbeFn = int (*)(const char*, const char*, long*);
  void* lib_ = nullptr;
  ProbeFn probe_ = nullptr;
};

// ---- log helpers --------------------------------------------------------------------------

/// The records of fault `id`, in log order.
std::vector<json> ofFault(const std::vector<json>& log, std::uint64_t id) {
  std::vector<json> out;
  for (const auto& r : log)
    if (r.contains(fd::kFaultId) && r[fd::kFaultId] == id) out.push_back(r);
  return out;
}

/// The fault_id of the first `injected` record of `component`.
std::uint64_t injectedId(const std::vector<json>& log, const std::string& component) {
  for (const auto& r : test::eventsOf(log, ev::kInjected))
    if (r[fd::kComponent] == component) return r[fd::kFaultId];
  ADD_FAILURE() << "no injected record of " << component;
  return 0;
}

/// The id of `component`'s first detected fault.
std::uint64_t detectedId(const std::vector<json>& log, const std::string& component) {
  for (const auto& r : test::eventsOf(log, ev::kDetected))
    if (r[fd::kComponent] == component) return r[fd::kFaultId];
  ADD_FAILURE() << "no detected record of " << component;
  return 0;
}

/// The first record of fault `id` with `event` (and `action`, for actions); null if none.
json record(const std::vector<json>& log, std::uint64_t id, const std::string& event, const std::string& action = "") {
  for (const auto& r : ofFault(log, id))
    if (r[fd::kEvent] == event && (action.empty() || r.value(fd::kAction, "") == action)) return r;
  return nullptr;
}

/// The position of that record in the log (for ordering), or -1.
long positionOf(const std::vector<json>& log, std::uint64_t id, const std::string& event,
                const std::string& action = "") {
  for (std::size_t i = 0; i < log.size(); ++i) {
    const json& r = log[i];
    if (r.contains(fd::kFaultId) && r[fd::kFaultId] == id && r[fd::kEvent] == event &&
        (action.empty() || r.value(fd::kAction, "") == action))
      return static_cast<long>(i);
  }
  return -1;
}

/// The `action` values logged for `component`, in order.
std::vector<std::string> actionsOf(const std::vector<json>& log, const std::string& component) {
  std::vector<std::string> out;
  for (const auto& r : test::eventsOf(log, ev::kAction))
    if (r.value(fd::kComponent, "") == component) out.push_back(r[fd::kAction]);
  return out;
}

/// A reset of `component` by fault `id`, end to end: detected → diagnosed reset → reset ok →
/// restore ok → recovered, in that order, and its state Active → Error → Active.
void expectResetTrace(const std::vector<json>& log, const std::string& component, std::uint64_t id,
                      const std::string& kind) {
  SCOPED_TRACE(component);
  json detected = record(log, id, ev::kDetected);
  ASSERT_FALSE(detected.is_null()) << "no detected record for fault " << id;
  EXPECT_EQ(detected[fd::kComponent], component);
  EXPECT_EQ(detected[fd::kKind], kind);
  json diagnosed = record(log, id, ev::kDiagnosed);
  ASSERT_FALSE(diagnosed.is_null());
  EXPECT_EQ(diagnosed[fd::kHandling], "reset");
  EXPECT_EQ(diagnosed[fd::kSeverity], "reset");
  EXPECT_EQ(diagnosed[fd::kRules], "fault_policy");
  json reset = record(log, id, ev::kAction, "reset");
  ASSERT_FALSE(reset.is_null());
  EXPECT_EQ(reset[fd::kOutcome], schema::kOk);
  EXPECT_EQ(reset[fd::kDetail], "onError → onReset → onRecover");
  json restore = record(log, id, ev::kAction, "restore");
  ASSERT_FALSE(restore.is_null());
  EXPECT_EQ(restore[fd::kOutcome], schema::kOk);
  json recovered = record(log, id, ev::kRecovered);
  ASSERT_FALSE(recovered.is_null()) << "no recovered record for fault " << id;
  EXPECT_EQ(recovered[fd::kComponent], component);
  const long p[] = {positionOf(log, id, ev::kInjected),          positionOf(log, id, ev::kDetected),
                    positionOf(log, id, ev::kDiagnosed),         positionOf(log, id, ev::kAction, "reset"),
                    positionOf(log, id, ev::kAction, "restore"), positionOf(log, id, ev::kRecovered)};
  for (std::size_t i = 1; i < std::size(p); ++i) EXPECT_LT(p[i - 1], p[i]) << "records out of order at " << i;
  // Each step at its own time: the rules are applied after the detection, the reset after both.
  EXPECT_LE(record(log, id, ev::kInjected)[fd::kTime].get<std::int64_t>(), detected[fd::kTime].get<std::int64_t>());
  EXPECT_LT(detected[fd::kTime].get<std::int64_t>(), diagnosed[fd::kTime].get<std::int64_t>());
  EXPECT_LE(diagnosed[fd::kTime].get<std::int64_t>(), reset[fd::kTime].get<std::int64_t>());
  // Its own state records of this fault: into Error with the detection, back to Active with the reset.
  std::vector<std::string> states;
  for (const auto& r : ofFault(log, id))
    if (r[fd::kEvent] == ev::kState) states.push_back(std::string(r[fd::kFrom]) + "→" + std::string(r[fd::kTo]));
  EXPECT_EQ(states, (std::vector<std::string>{"Active→Error", "Error→Active"}));
}

/// The checkpoint age the restore record gives ("... of 12.345 ms before").
double restoredAgeMs(const json& restore) {
  const std::string d = restore[fd::kDetail];
  const auto at = d.find("checkpoint of ");
  if (at == std::string::npos) return -1;
  return std::stod(d.substr(at + 14));
}

// ---- 1. reset ------------------------------------------------------------------------------

TEST_F(Handling, ResetRestoresTheCounterFromItsCheckpoint) {
  start("reset.xml", "reset_faults.xml");
  ASSERT_TRUE(waitFor([&] { return recovered("tally") && recovered("fresh"); })) << "not recovered";
  ASSERT_TRUE(keepsExecuting("tally", 20));
  ASSERT_TRUE(keepsExecuting("fresh", 20));
  EXPECT_TRUE(keepsExecuting("bystander", 10));
  ASSERT_TRUE(waitFor([&] { return probeOr0("tally_tap", "last") > probeOr0("tally", "at_error") + 10; }));
  const std::vector<json> log = finish();

  // tally (checkpoint every 20 ms, 5 ms period): back to a count a few steps before the fault.
  const long at_error = probeOr0("tally", "at_error"), restored = probeOr0("tally", "restored");
  EXPECT_GT(at_error, 20) << "the fault came after ~60 counts";
  EXPECT_GT(restored, 0) << "restarted from 0 instead of the checkpoint";
  EXPECT_LE(restored, at_error);
  EXPECT_LE(at_error - restored, 10) << "more lost than between two checkpoints";
  EXPECT_EQ(probeOr0("tally", "resets"), 1);
  // Downstream: the count fell back exactly to the restored value + 1, never to 1.
  EXPECT_EQ(probeOr0("tally_tap", "max_drop"), std::max(0L, at_error - restored - 1));

  // fresh (no <checkpoint>): only the checkpoint after onStart, the count starts over.
  const long fresh_error = probeOr0("fresh", "at_error");
  EXPECT_GT(fresh_error, 20);
  EXPECT_EQ(probe("fresh", "restored"), 0L);
  EXPECT_EQ(probeOr0("fresh_tap", "max_drop"), fresh_error - 1);

  const std::uint64_t tally_id = injectedId(log, "tally"), fresh_id = injectedId(log, "fresh");
  expectResetTrace(log, "tally", tally_id, "signal");
  expectResetTrace(log, "fresh", fresh_id, "signal");
  const double tally_age = restoredAgeMs(record(log, tally_id, ev::kAction, "restore"));
  const double fresh_age = restoredAgeMs(record(log, fresh_id, ev::kAction, "restore"));
  EXPECT_GE(tally_age, 0);
  EXPECT_LT(tally_age, 200) << "periodic checkpoint (20 ms) not taken";
  EXPECT_GT(fresh_age, 299) << "the start checkpoint comes before the fault at 300 ms";

  auto h = handlingsOf("tally");
  ASSERT_EQ(h.size(), 1u);
  EXPECT_EQ(h[0].actions, "reset, restore");
  EXPECT_FALSE(h[0].failed);
  EXPECT_EQ(h[0].severity, "reset");
  EXPECT_GT(h[0].recovered_ns, h[0].detected_ns);
  EXPECT_TRUE(handlingsOf("bystander").empty());
}

// A passive component's <checkpoint period> is taken between its calls (under its lock, after a
// call that did not fault): its reset restores the count of a recent call, not of its start.
TEST_F(Handling, APassiveComponentIsCheckpointedBetweenItsCallsAndResetToARecentCount) {
  start("passive_reset.xml", "");
  ASSERT_TRUE(waitFor([&] { return recovered("tally") && recovered("fresh"); })) << "not recovered";
  ASSERT_TRUE(waitFor([&] { return probeOr0("tally_client", "last") > 60 && probeOr0("fresh_client", "last") > 30; }));
  const std::vector<json> log = finish();

  EXPECT_EQ(probeOr0("tally", "at_error"), 40);
  const long restored = probeOr0("tally", "restored");
  EXPECT_GT(restored, 0) << "restarted from 0 instead of a checkpoint between calls";
  EXPECT_LT(restored, 40) << "the faulty call's count was checkpointed";
  EXPECT_EQ(probeOr0("tally_client", "max_drop"), std::max(0L, 38 - restored));  // 39, then restored + 1
  // fresh (no <checkpoint>): only the checkpoint after onStart, the count starts over.
  EXPECT_EQ(probeOr0("fresh", "at_error"), 40);
  EXPECT_EQ(probe("fresh", "restored"), 0L);
  EXPECT_EQ(probeOr0("fresh_client", "max_drop"), 38);
  EXPECT_GT(restoredAgeMs(record(log, detectedId(log, "fresh"), ev::kAction, "restore")),
            restoredAgeMs(record(log, detectedId(log, "tally"), ev::kAction, "restore")));
}

// ---- 2. replacement ------------------------------------------------------------------------

TEST_F(Handling, AnAlternativeColdOrPreloadedTakesOverWithTheCheckpointedCount) {
  start("replace.xml", "replace_segfault.xml");
  ASSERT_TRUE(waitFor([&] { return recovered("cold") && recovered("warm"); })) << "not recovered";
  ASSERT_TRUE(waitFor(
      [&] { return probeOr0("cold", "backup.executions") > 20 && probeOr0("warm", "backup.executions") > 20; }));
  EXPECT_TRUE(keepsExecuting("bystander", 10));
  for (const std::string name : {"cold", "warm"}) {
    SCOPED_TRACE(name);
    Component* now = engine_->find(name);
    ASSERT_NE(now, nullptr);
    EXPECT_EQ(runtime::coreOf(*now).class_name, "TallyBackup");
    EXPECT_EQ(now->instanceName(), name);
    EXPECT_EQ(now->state(), State::Active);
    EXPECT_GT(executions(name), 20u);
  }
  const std::vector<json> log = finish();

  for (const std::string name : {"cold", "warm"}) {
    SCOPED_TRACE(name);
    // The primary's last count, and where the alternative started from (its onStart).
    const long last = probeOr0(name, "n"), start_n = probeOr0(name, "backup.start_n");
    EXPECT_GT(last, 20);
    EXPECT_GT(start_n, 0) << "the alternative started from 0, not from the checkpoint";
    EXPECT_LE(start_n, last);
    EXPECT_LE(last - start_n, 10);
    EXPECT_EQ(probeOr0(name, "backup.initialized"), 1) << "one alternative, initialized once";
    EXPECT_EQ(probeOr0(name, "backup.starts"), 1);
    // The tap kept receiving, now from the alternative, continuing the count.
    const std::string tap = name + "_tap";
    EXPECT_GT(probeOr0(tap, "last"), last + 10);
    EXPECT_EQ(probeOr0(tap, "max_drop"), std::max(0L, last - start_n - 1));

    const std::uint64_t id = injectedId(log, name);
    json diagnosed = record(log, id, ev::kDiagnosed);
    ASSERT_FALSE(diagnosed.is_null());
    EXPECT_EQ(diagnosed[fd::kSeverity], "stop");
    EXPECT_EQ(diagnosed[fd::kHandling], "replace");
    json replace = record(log, id, ev::kAction, "replace");
    ASSERT_FALSE(replace.is_null());
    EXPECT_EQ(replace[fd::kOutcome], schema::kOk);
    EXPECT_EQ(replace[fd::kReplacement], "TallyBackup");
    EXPECT_NE(replace[fd::kDetail].get<std::string>().find("with the checkpointed state"), std::string::npos)
        << replace;
    EXPECT_TRUE(record(log, id, ev::kAction, "stop").is_null()) << "replaced, not stopped";
    json recovered = record(log, id, ev::kRecovered);
    ASSERT_FALSE(recovered.is_null());
    EXPECT_LT(positionOf(log, id, ev::kAction, "replace"), positionOf(log, id, ev::kRecovered));
    EXPECT_EQ(actionsOf(log, name), std::vector<std::string>{"replace"});
  }
  EXPECT_NE(record(log, injectedId(log, "cold"), ev::kAction, "replace")[fd::kDetail].get<std::string>().find(
                "loaded at fault time"),
            std::string::npos);
  EXPECT_NE(record(log, injectedId(log, "warm"), ev::kAction, "replace")[fd::kDetail].get<std::string>().find(
                "(preloaded)"),
            std::string::npos);
  EXPECT_TRUE(engine_->faultManager().stoppedComponents().empty());
}

/// Each object's `state` records chain from Created to Destroyed: every `from` is the previous
/// record's `to`.
void expectWholeStory(const std::vector<json>& records) {
  ASSERT_FALSE(records.empty());
  EXPECT_EQ(records.front()[fd::kFrom], "Created") << records.front();
  for (std::size_t i = 1; i < records.size(); ++i)
    EXPECT_EQ(records[i][fd::kFrom], records[i - 1][fd::kTo]) << "record " << i << ": " << records[i];
  EXPECT_EQ(records.back()[fd::kTo], "Destroyed") << records.back();
}

// A preloaded alternative standing by has a story of its own, out of service throughout; the
// name's own states are its primary's.
TEST_F(Handling, APreloadedAlternativeStandingByHasRecordsOfItsOwnOutOfService) {
  start("replace.xml", "");  // no fault: `warm`'s preloaded alternative stands by to the end
  EXPECT_TRUE(keepsExecuting("warm", 10));
  const std::vector<json> log = finish();
  EXPECT_EQ(test::statesOf(log, "warm"), (std::vector<std::string>{"Ready", "Active", "Inactive", "Destroyed"}));
  const auto alternative = test::objectStatesOf(log, "warm", true);
  expectWholeStory(alternative);
  EXPECT_EQ(alternative.size(), 2u);  // Created → Ready, Ready → Destroyed
  for (const auto& r : alternative) {
    EXPECT_EQ(r[fd::kClass], "TallyBackup") << r;
    EXPECT_EQ(r.value(fd::kServing, true), false) << r;
  }
  for (const auto& r : test::objectStatesOf(log, "warm", false)) {
    EXPECT_EQ(r[fd::kClass], "Tally") << r;
    EXPECT_FALSE(r.contains(fd::kServing)) << r;
  }
  EXPECT_TRUE(test::objectStatesOf(log, "cold", true).empty()) << "a cold alternative is loaded at fault time";
}

// After a replacement the log tells both objects' stories whole: the failed component's ends in
// Destroyed, out of service; the alternative's, marked as its, runs from its creation through
// the switch (with the fault's id) to its own end.
TEST_F(Handling, AReplacementTellsTheFailedComponentsAndTheAlternativesStoriesWhole) {
  start("replace.xml", "replace_segfault.xml");  // both replaced
  ASSERT_TRUE(waitFor([&] { return recovered("cold") && recovered("warm"); })) << "not recovered";
  const std::vector<json> log = finish();
  for (const std::string name : {"cold", "warm"}) {
    SCOPED_TRACE(name);
    const std::uint64_t id = injectedId(log, name);
    const auto failed = test::objectStatesOf(log, name, false);
    expectWholeStory(failed);
    for (const auto& r : failed) EXPECT_EQ(r[fd::kClass], "Tally") << r;
    ASSERT_GE(failed.size(), 2u);
    const json& error = failed[failed.size() - 2];
    EXPECT_EQ(error[fd::kTo], "Error") << error;
    EXPECT_EQ(error.value(fd::kFaultId, std::uint64_t{0}), id) << error;
    EXPECT_EQ(failed.back().value(fd::kServing, true), false) << "replaced, it ends out of service";

    const auto alternative = test::objectStatesOf(log, name, true);
    expectWholeStory(alternative);
    const auto took_over = std::find_if(alternative.begin(), alternative.end(),
                                        [](const json& r) { return r[fd::kTo] == "Active"; });
    ASSERT_NE(took_over, alternative.end());
    EXPECT_EQ(took_over->value(fd::kFaultId, std::uint64_t{0}), id) << *took_over;
    for (auto r = alternative.begin(); r != alternative.end(); ++r) {
      EXPECT_EQ((*r)[fd::kClass], "TallyBackup") << *r;
      EXPECT_EQ(r->value(fd::kServing, true), r >= took_over) << "serving from the switch on: " << *r;
    }
    // The name's own states: the primary's up to the fault, then the alternative's.
    const auto states = test::statesOf(log, name);
    EXPECT_EQ(std::count(states.begin(), states.end(), "Destroyed"), 1);
    EXPECT_EQ(states.back(), "Destroyed");
  }
}

/// Whether a file named `library` is mapped into this process (/proc/self/maps).
bool mapped(const std::string& library) {
  std::ifstream maps("/proc/self/maps");
  for (std::string line; std::getline(maps, line);)
    if (line.size() >= library.size() && line.compare(line.size() - library.size(), library.size(), library) == 0)
      return true;
  return false;
}

// A cold replacement loads code at fault time: the alternative's library (its only component)
// is not in the process until the fault, then it is, and the alternative counts on from the
// checkpoint. The fault is armed by the test, not by a scenario's clock, so that "before the
// fault" is certain on a loaded machine.
TEST_F(Handling, AColdAlternativesLibraryIsLoadedOnlyAtFaultTimeAndTakesOverFromTheCheckpoint) {
  const std::string library = "/libkeel_test_cold_spare.so";
  engine::Engine& e = start("replace_cold.xml", "");
  ASSERT_TRUE(waitFor([&] { return probeOr0("cold", "n") > 20; }));
  ASSERT_FALSE(mapped(library)) << "the cold alternative's library was loaded before any fault";
  const std::uint64_t id = e.faultManager().nextId();
  ASSERT_TRUE(runtime::arm(*e.find("cold"), runtime::InjectKind::Throw, id));
  ASSERT_TRUE(waitFor([&] { return recovered("cold"); })) << "not recovered";
  EXPECT_TRUE(mapped(library)) << "replaced without loading the alternative's library";
  Component* now = e.find("cold");
  ASSERT_NE(now, nullptr);
  EXPECT_EQ(runtime::coreOf(*now).class_name, "TallyColdSpare");
  EXPECT_EQ(now->state(), State::Active);
  // The tap downstream sees the count go on from the checkpoint (taken every 20 ms, 5 ms per
  // count), well past where the primary stopped.
  const long last = probeOr0("cold", "n");
  ASSERT_TRUE(waitFor([&] { return probeOr0("cold_tap", "last") > last + 20; }))
      << "the alternative publishes nothing: tap at " << probeOr0("cold_tap", "last") << ", primary at " << last;
  EXPECT_LE(probeOr0("cold_tap", "max_drop"), 10) << "the alternative did not start from the checkpoint";
  const std::vector<json> log = finish();
  json replace = record(log, id, ev::kAction, "replace");
  ASSERT_FALSE(replace.is_null());
  EXPECT_EQ(replace[fd::kOutcome], schema::kOk);
  EXPECT_EQ(replace[fd::kReplacement], "TallyColdSpare");
  EXPECT_NE(replace[fd::kDetail].get<std::string>().find("loaded at fault time"), std::string::npos) << replace;
}

// ---- 3. fault stop over Fig. 7 -------------------------------------------------------------

class HandlingFaultStop : public Handling {
 protected:
  /// Runs Fig. 7 with `scenario` until `components` are fault-stopped; checks which
  /// applications stopped (engine and log) and that those that keep running still execute
  /// while the stopped components do not.
  std::vector<json> run(const std::string& scenario, const std::set<std::string>& components,
                        const std::set<std::string>& applications) {
    start("fig7/system.xml", scenario);
    auto& fm = engine_->faultManager();
    EXPECT_TRUE(waitFor([&] { return fm.stoppedComponents() == components; }))
        << "stopped: " << ::testing::PrintToString(fm.stoppedComponents());
    EXPECT_EQ(fm.stoppedApplications(), applications);
    // Stopped components reach Inactive (their onStop ran on their executors); the faulty
    // ones stay in Error.
    for (const auto& name : components) {
      EXPECT_TRUE(waitFor([&] {
        State s = engine_->find(name)->state();
        return s == State::Inactive || s == State::Error;
      })) << name
          << " not stopped";
    }
    const std::set<std::string> all_counters = {"A.b1", "A.b2", "A.b3", "B.b1", "B.b2"};
    std::map<std::string, std::uint64_t> before;
    for (const auto& c : all_counters) before[c] = executions(c);
    for (const auto& c : all_counters) {
      if (components.count(c)) continue;
      EXPECT_TRUE(keepsExecuting(c, 10)) << c << " should keep running";
    }
    for (const auto& c : all_counters) {
      if (components.count(c)) {
        EXPECT_EQ(executions(c), before[c]) << c << " stopped but executes";
      }
    }
    for (const std::string app : {"A", "B", "C", "D"}) {
      for (const char* inst : {"a1", "c1", "b1"}) {
        const std::string name = app + "." + inst;
        Component* c = engine_->find(name);
        if (c == nullptr || components.count(name)) continue;
        EXPECT_EQ(c->state(), State::Active) << app << "." << inst;
      }
    }
    std::vector<json> log = finish();
    std::set<std::string> logged_apps;
    for (const auto& r : test::eventsOf(log, ev::kState)) {
      if (!r.contains(fd::kApplication)) continue;
      EXPECT_EQ(r[fd::kFrom], "running");
      EXPECT_EQ(r[fd::kTo], "stopped");
      EXPECT_TRUE(logged_apps.insert(r[fd::kApplication]).second) << "stopped twice: " << r;
    }
    EXPECT_EQ(logged_apps, applications);
    std::set<std::string> logged_components, logged_stop_apps;
    for (const auto& r : test::eventsOf(log, ev::kAction)) {
      if (r[fd::kAction] != "stop") continue;
      EXPECT_EQ(r[fd::kOutcome], schema::kOk) << r;
      for (const auto& c : r[fd::kComponents]) EXPECT_TRUE(logged_components.insert(c).second) << "listed twice: " << c;
      for (const auto& a : r[fd::kApplications]) logged_stop_apps.insert(a);
    }
    EXPECT_EQ(logged_components, components);
    EXPECT_EQ(logged_stop_apps, applications);
    return log;
  }
};

TEST_F(HandlingFaultStop, AFaultOfBsPairStopsItsExecutorAndApplicationsBAndCWhileAAndDRun) {
  auto log = run("fig7/pair_b2.xml", {"B.b1", "B.b2", "B.a1", "C.a1", "C.c1"}, {"B", "C"});
  json stop = record(log, injectedId(log, "B.b2"), ev::kAction, "stop");
  ASSERT_FALSE(stop.is_null());
  EXPECT_EQ(stop[fd::kScope], "executor");
  EXPECT_EQ(record(log, injectedId(log, "B.b2"), ev::kDiagnosed)[fd::kSeverity], "stop");
}

TEST_F(HandlingFaultStop, ThePapersRedComponentsStopBAndCButAKeepsItsLastSensorAndDRuns) {
  // Fig. 7: A runs in spite of two faulty type-B components, B cannot, C (needs B) stops, D runs.
  auto log = run("fig7/paper.xml", {"A.b1", "A.b2", "B.b1", "B.b2", "B.a1", "C.a1", "C.c1"}, {"B", "C"});
  for (const std::string c : {"A.b1", "A.b2", "B.b1"}) {
    const std::uint64_t id = injectedId(log, c);
    json diagnosed = record(log, id, ev::kDiagnosed);
    ASSERT_FALSE(diagnosed.is_null()) << c;
    EXPECT_EQ(diagnosed[fd::kRules], "none (contained, not recovered)");
    json stop = record(log, id, ev::kAction, "stop");
    ASSERT_FALSE(stop.is_null()) << c;
    EXPECT_EQ(stop[fd::kScope], "component");
  }
  // A's first faults stop nothing but the component; B's b1 takes the pair and C along.
  json first = record(log, injectedId(log, "A.b1"), ev::kAction, "stop");
  EXPECT_EQ(first[fd::kComponents], json::array({"A.b1"}));
  EXPECT_EQ(first[fd::kApplications], json::array());
  json pair = record(log, injectedId(log, "B.b1"), ev::kAction, "stop");
  EXPECT_EQ(std::set<std::string>(pair[fd::kApplications].begin(), pair[fd::kApplications].end()),
            (std::set<std::string>{"B", "C"}));
}

TEST_F(HandlingFaultStop, AFaultOfAsB3StopsTheSensorsTaskSoAAndDStopWhileBAndCRun) {
  auto log = run("fig7/sensors_b3.xml", {"A.b1", "A.b2", "A.b3", "A.a1", "D.a1", "D.c1"}, {"A", "D"});
  json stop = record(log, injectedId(log, "A.b3"), ev::kAction, "stop");
  ASSERT_FALSE(stop.is_null());
  EXPECT_EQ(stop[fd::kScope], "executor");
  EXPECT_EQ(record(log, injectedId(log, "A.b3"), ev::kDetected)[fd::kKind], "error_code");
}

// ---- 4. emergency stop ---------------------------------------------------------------------

TEST_F(Handling, AnEmergencyFaultStopsTheActuatorInNeutralUntilTheEmergencyIsCleared) {
  auto& engine = start("emergency.xml", "emergency_segfault.xml");
  Component* actuator = engine.find("actuator");
  ASSERT_NE(actuator, nullptr);
  ASSERT_TRUE(waitFor([&] { return probeOr0("actuator", "estops") == 1; })) << "onEmergencyStop never ran";
  EXPECT_TRUE(engine.faultManager().emergencyLatched());
  EXPECT_TRUE(actuator->emergencyLatched());
  EXPECT_EQ(probe("actuator", "cmd_milli"), 0L);
  ASSERT_TRUE(waitFor([&] { return probe("motor", "last_milli") == 0L; })) << "neutral never reached the motor";

  // Latched: many cycles later the actuator still executes, and still commands neutral.
  const long latched_runs = probeOr0("actuator", "executions_latched");
  ASSERT_TRUE(waitFor([&] { return probeOr0("actuator", "executions_latched") >= latched_runs + 10; }));
  EXPECT_TRUE(actuator->emergencyLatched());
  EXPECT_EQ(probe("actuator", "cmd_milli"), 0L);
  EXPECT_EQ(probe("motor", "last_milli"), 0L);
  EXPECT_EQ(probeOr0("actuator", "estops"), 1) << "onEmergencyStop once per emergency";
  EXPECT_TRUE(keepsExecuting("bystander", 10)) << "an emergency stops actuators, not the other components";

  // Cleared explicitly: it may move again.
  EXPECT_TRUE(engine.clearEmergency("test"));
  EXPECT_FALSE(engine.clearEmergency("test")) << "nothing left to clear";
  EXPECT_FALSE(actuator->emergencyLatched());
  EXPECT_TRUE(
      waitFor([&] { return probeOr0("actuator", "cmd_milli") >= 1000 && probeOr0("motor", "last_milli") >= 1000; }));
  EXPECT_EQ(probeOr0("actuator", "overlaps"), 0) << "onEmergencyStop overlapped another callback";
  const std::set<std::string> stopped = engine.faultManager().stoppedComponents();
  const std::vector<json> log = finish();

  const std::uint64_t id = injectedId(log, "trigger");
  EXPECT_EQ(record(log, id, ev::kDiagnosed)[fd::kSeverity], "emergency");
  EXPECT_EQ(record(log, id, ev::kDiagnosed)[fd::kHandling], "emergency");
  std::vector<json> em = test::eventsOf(log, ev::kEmergency);
  ASSERT_EQ(em.size(), 2u);
  EXPECT_EQ(em[0][fd::kPhase], "latched");
  EXPECT_NE(em[0][fd::kBy].get<std::string>().find("trigger"), std::string::npos) << em[0];
  EXPECT_EQ(em[1][fd::kPhase], "cleared");
  EXPECT_EQ(em[1][fd::kBy], "test");
  json estop;
  for (const auto& r : test::eventsOf(log, ev::kAction))
    if (r[fd::kAction] == "emergency_stop") estop = r;
  ASSERT_FALSE(estop.is_null());
  EXPECT_EQ(estop[fd::kOutcome], schema::kOk);
  std::set<std::string> ran(estop[fd::kComponents].begin(), estop[fd::kComponents].end());
  EXPECT_TRUE(ran.count("actuator") && ran.count("motor")) << estop;
  // Then as stop: the trigger (scope component) is stopped, nothing else.
  EXPECT_EQ(stopped, std::set<std::string>{"trigger"});
  EXPECT_LT(positionOf(log, id, ev::kDetected), positionOf(log, id, ev::kAction, "stop"));
  long latched_at = -1, cleared_at = -1;
  for (std::size_t i = 0; i < log.size(); ++i) {
    if (log[i][fd::kEvent] == ev::kEmergency && log[i][fd::kPhase] == "latched") latched_at = static_cast<long>(i);
    if (log[i][fd::kEvent] == ev::kEmergency && log[i][fd::kPhase] == "cleared") cleared_at = static_cast<long>(i);
  }
  EXPECT_LT(positionOf(log, id, ev::kDetected), latched_at);
  EXPECT_LT(latched_at, cleared_at);
}

TEST_F(Handling, AnOperatorsEmergencyStopLatchesWithoutAFault) {
  auto& engine = start("emergency.xml", "");
  ASSERT_TRUE(waitFor([&] { return probeOr0("actuator", "cmd_milli") >= 1000; }));
  const auto ran = engine.emergencyStop("operator");
  EXPECT_NE(std::find(ran.begin(), ran.end(), "actuator"), ran.end());
  EXPECT_TRUE(waitFor([&] { return probeOr0("actuator", "estops") == 1; }));
  EXPECT_TRUE(engine.find("actuator")->emergencyLatched());
  ASSERT_TRUE(waitFor([&] { return probe("motor", "last_milli") == 0L; }));
  const long latched_runs = probeOr0("actuator", "executions_latched");
  ASSERT_TRUE(waitFor([&] { return probeOr0("actuator", "executions_latched") >= latched_runs + 5; }));
  EXPECT_EQ(probe("actuator", "cmd_milli"), 0L);
  EXPECT_TRUE(engine.clearEmergency("operator"));
  EXPECT_TRUE(waitFor([&] { return probeOr0("motor", "last_milli") >= 1000; }));
  const std::vector<json> log = finish();
  EXPECT_TRUE(test::eventsOf(log, ev::kDetected).empty());
  auto em = test::eventsOf(log, ev::kEmergency);
  ASSERT_EQ(em.size(), 2u);
  EXPECT_EQ(em[0][fd::kBy], "operator");
  EXPECT_EQ(em[1][fd::kPhase], "cleared");
}

// ---- 5. escalation -------------------------------------------------------------------------

TEST_F(Handling, PastTheRestartIntensityAResetEscalatesToTheAlternativeThenToStopAndEnds) {
  start("escalate.xml", "escalate_repeated.xml");
  auto& fm = engine_->faultManager();
  auto ended = [&](const std::string& c, std::size_t n) {
    auto h = handlingsOf(c);
    return h.size() >= n && h.back().actions.size() >= 4 &&
           h.back().actions.compare(h.back().actions.size() - 4, 4, "stop") == 0;
  };
  ASSERT_TRUE(waitFor([&] { return ended("flaky", 4) && ended("no_alt", 3); }, 3000ms)) << [&] {
    std::string d;
    for (const auto& h : fm.handlings()) d += h.component + ": " + h.actions + "\n";
    return d;
  }();
  // It never loops: nothing more happens once the component is stopped.
  EXPECT_TRUE(keepsExecuting("bystander", 20));
  EXPECT_EQ(handlingsOf("flaky").size(), 4u);
  EXPECT_EQ(handlingsOf("no_alt").size(), 3u);
  EXPECT_EQ(runtime::coreOf(*engine_->find("flaky")).class_name, "TallyBackup");
  EXPECT_EQ(fm.stoppedComponents(), (std::set<std::string>{"flaky", "no_alt"}));
  EXPECT_EQ(engine_->find("no_alt")->state(), State::Error);
  const std::uint64_t no_alt_runs = executions("no_alt");
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(executions("no_alt"), no_alt_runs);
  const std::vector<json> log = finish();

  auto actions = [](const std::vector<fault::Handling>& hs) {
    std::vector<std::string> out;
    out.reserve(hs.size());
    for (const auto& h : hs) out.push_back(h.actions);
    return out;
  };
  // Two resets; the third fault exceeds 2 recoveries in 10 s: escalate to the alternative; a
  // fault of the alternative escalates to stop (no second replacement).
  EXPECT_EQ(actions(handlingsOf("flaky")),
            (std::vector<std::string>{"reset, restore", "reset, restore", "escalate, replace", "escalate, stop"}));
  EXPECT_EQ(actions(handlingsOf("no_alt")),
            (std::vector<std::string>{"reset, restore", "reset, restore", "escalate, stop"}));
  EXPECT_EQ(actionsOf(log, "flaky"), (std::vector<std::string>{"reset", "restore", "reset", "restore", "escalate",
                                                               "replace", "escalate", "stop"}));
  std::vector<std::string> escalations;
  for (const auto& r : test::eventsOf(log, ev::kAction))
    if (r[fd::kAction] == "escalate" && r[fd::kComponent] == "flaky") escalations.push_back(r[fd::kDetail]);
  ASSERT_EQ(escalations.size(), 2u);
  EXPECT_EQ(escalations[0], "reset → replace: more than 2 recoveries within 10000 ms");
  EXPECT_EQ(escalations[1].rfind("reset → stop", 0), 0u) << escalations[1];
  for (const auto& r : test::eventsOf(log, ev::kAction)) {
    if (r[fd::kAction] == "replace") {
      EXPECT_EQ(r[fd::kReplacement], "TallyBackup");
    }
  }
  EXPECT_EQ(probeOr0("flaky", "resets"), 2) << "the primary was reset twice";
  EXPECT_EQ(probeOr0("flaky", "backup.recovers"), 0) << "the alternative was never reset";
  EXPECT_EQ(probeOr0("no_alt", "resets"), 2);
  // no_alt's fourth fault never fires (armed, never injected): a stopped component stays in
  // Error and is not executed.
  int detected = 0, injected = 0;
  for (const auto& r : log) {
    if (r.value(fd::kComponent, "") != "no_alt") continue;
    detected += r[fd::kEvent] == ev::kDetected;
    injected += r[fd::kEvent] == ev::kInjected && r.value(fd::kDetected, true);
  }
  EXPECT_EQ(detected, 3);
  EXPECT_EQ(injected, 3);
}

// ---- 6. checkpoints under concurrent execution ---------------------------------------------

TEST_F(Handling, CheckpointsTakenEveryCycleOnSeveralExecutorsAreNeverTornAndLoseAtMostACycle) {
  start("checkpoints.xml", "checkpoints_faults.xml");
  const std::vector<std::string> reset_twins = {"twin_a", "twin_b", "twin_c", "twin_d"};
  ASSERT_TRUE(waitFor(
      [&] {
        for (const auto& t : reset_twins)
          if (!recovered(t, 6)) return false;
        return recovered("twin_e");
      },
      3000ms))
      << "not every fault recovered";
  for (const auto& t : reset_twins) EXPECT_TRUE(keepsExecuting(t, 10)) << t;
  EXPECT_TRUE(keepsExecuting("twin_e", 10));
  EXPECT_EQ(runtime::coreOf(*engine_->find("twin_e")).class_name, "Twin");
  const std::vector<json> log = finish();

  for (const auto& t : reset_twins) {
    SCOPED_TRACE(t);
    EXPECT_EQ(probeOr0(t, "torn"), 0) << "a torn checkpoint was restored";
    EXPECT_EQ(probeOr0(t, "overlaps"), 0);
    EXPECT_EQ(probeOr0(t, "recovers"), 6);
    EXPECT_GE(probeOr0(t, "min_lost"), 0) << "restored a state newer than the fault";
    EXPECT_LE(probeOr0(t, "max_lost"), 5) << "checkpointed every cycle";
    for (const auto& h : handlingsOf(t)) {
      EXPECT_EQ(h.actions, "reset, restore");
      EXPECT_FALSE(h.failed);
    }
  }
  // twin_e's replacement (a second Twin, loaded at fault time) started from the checkpoint.
  EXPECT_EQ(probeOr0("twin_e", "torn"), 0);
  EXPECT_EQ(probeOr0("twin_e", "starts"), 2);
  EXPECT_GT(probeOr0("twin_e", "start_value"), 0) << "the alternative started from scratch";
  auto he = handlingsOf("twin_e");
  ASSERT_EQ(he.size(), 1u);
  EXPECT_EQ(he[0].actions, "replace");
  int resets = 0;
  for (const auto& r : test::eventsOf(log, ev::kAction))
    resets += r[fd::kAction] == "reset" && r[fd::kOutcome] == schema::kOk;
  EXPECT_EQ(resets, 24);
  EXPECT_EQ(test::eventsOf(log, ev::kRecovered).size(), 25u);
}

// ---- 7. hung callback ----------------------------------------------------------------------

TEST_F(Handling, AHungCallbackIsInterruptedAndTheComponentIsResetAndExecutesAgain) {
  start("hang.xml", "hang_injected.xml");
  ASSERT_TRUE(waitFor([&] { return recovered("hanger"); }, 5000ms)) << "the hung callback was never interrupted";
  EXPECT_TRUE(keepsExecuting("hanger", 20));
  EXPECT_TRUE(keepsExecuting("mate", 20)) << "the shared executor is free again";
  EXPECT_TRUE(keepsExecuting("bystander", 10));
  EXPECT_EQ(engine_->find("hanger")->state(), State::Active);
  const std::vector<json> log = finish();

  const std::uint64_t id = injectedId(log, "hanger");
  json detected = record(log, id, ev::kDetected);
  ASSERT_FALSE(detected.is_null());
  EXPECT_EQ(detected[fd::kDetector], "watchdog");
  EXPECT_NE(detected[fd::kDetail].get<std::string>().find("a callback has not returned"), std::string::npos);
  expectResetTrace(log, "hanger", id, "heartbeat");
  EXPECT_EQ(probeOr0("hanger", "resets"), 1);
  EXPECT_GT(probeOr0("hanger", "restored"), 0);
  EXPECT_TRUE(engine_->faultManager().stoppedComponents().empty());
}

}  // namespace
}  // namespace keel
