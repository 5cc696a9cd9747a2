#include "soak/campaign.hpp"

#include <fmt/format.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include "engine/engine.hpp"
#include "injection/scenario.hpp"
#include "keel/hardware_driver.hpp"
#include "log/schema.hpp"
#include "plan/property_settings.hpp"
#include "profile/loader.hpp"
#include "soak/fault_menu.hpp"

namespace keel::soak {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The soak's scratch directory (round scenarios, the log when none is given), removed at the end.
struct ScratchDir {
  fs::path path;
  ScratchDir() {
    std::string pattern = (fs::temp_directory_path() / "keel-soak-XXXXXX").string();
    if (::mkdtemp(pattern.data())) path = pattern;
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  ~ScratchDir() {
    std::error_code ec;
    if (!path.empty()) fs::remove_all(path, ec);
  }
};

std::string joined(const profile::Diagnostics& ds) {
  std::string s;
  for (const auto& d : ds) {
    if (!s.empty()) s += '\n';  // (not `"\n" + d.str()`: GCC 12's -O3 sees a false -Wrestrict there)
    s += d.str();
  }
  return s;
}

/// The profile planned with the --set options applied.
Result<plan::PlannedProfiles> planned(const SoakOptions& o, std::vector<plan::PropertySetting>& settings) {
  auto set = profile::load(o.profile);
  if (!set) return fail(joined(set.error()));
  auto p = plan::planProfiles(std::move(*set));
  if (!p) return p.error();
  settings.clear();
  for (const auto& text : o.sets) {
    auto s = plan::parsePropertySetting(text);
    if (!s) return s.error();
    settings.push_back(std::move(*s));
  }
  if (auto r = plan::applyPropertySettings(p->plan, settings); !r) return r.error();
  return p;
}

engine::EngineOptions engineOptions(const SoakOptions& o) {
  engine::EngineOptions eo;
  eo.warn = [](const std::string&) {};  // in the log: a soak's kills and hangs warn by design
  if (!o.host_executable.empty()) eo.host_launch.executable = o.host_executable;
  return eo;
}

/// The application's fault menu: its plan, and what its hardware drivers offer (its components
/// made, not started).
Result<std::vector<Offer>> menuOf(const SoakOptions& o) {
  std::vector<plan::PropertySetting> settings;
  auto p = planned(o, settings);
  if (!p) return p.error();
  engine::EngineOptions eo = engineOptions(o);
  eo.property_settings = settings;
  auto e = engine::Engine::create(std::move(*p), std::move(eo));
  if (!e) return e.error();
  HardwareOffers offers;
  for (const auto& inst : (*e)->instances())
    if (const auto* driver = dynamic_cast<const HardwareDriver*>(inst.component.get()))
      if (auto faults = driver->simulatedFaults(); !faults.empty()) offers[inst.plan->name] = std::move(faults);
  return faultMenu((*e)->plan(), offers);
}

std::uint64_t fileSize(const std::string& path) {
  std::error_code ec;
  const auto n = fs::file_size(path, ec);
  return ec ? 0 : n;
}

std::string readFrom(const std::string& path, std::uint64_t offset) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(offset));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Waits up to `limit` for the processes a round started to be gone; what is left.
std::vector<std::string> leftovers(std::chrono::milliseconds limit) {
  const auto end = Clock::now() + limit;
  std::vector<std::string> left = childrenNow();
  while (!left.empty() && Clock::now() < end) {
    std::this_thread::sleep_for(50ms);
    left = childrenNow();
  }
  return left;
}

class Campaign {
 public:
  Campaign(const SoakOptions& o, std::function<void(const SoakProgress&)> progress)
      : o_(o), progress_(std::move(progress)), rng_(o.seed) {}

  Result<SoakResult> run() {
    if (scratch_.path.empty()) return fail("cannot make a temporary directory for the soak's scenarios");
    log_ = o_.log.empty() ? (scratch_.path / "soak.jsonl").string() : fs::absolute(o_.log).string();
    auto menu = menuOf(o_);
    if (!menu) return menu.error();
    menu_ = std::move(*menu);
    if (menu_.empty()) return fail(fmt::format("{}: no component offers a fault to inject", o_.profile));
    t0_ = Clock::now();
    const double total_s = o_.minutes * 60;
    while (secondsSince(t0_) < total_s && r_.violations.empty()) {
      if (auto ok = round(total_s); !ok) {
        if (r_.rounds == 1) return ok.error();  // the application does not run at all
        r_.violations.push_back(fmt::format("round {}: {}", r_.rounds, ok.error().message));
      }
    }
    r_.seconds = secondsSince(t0_);
    if (r_.baseline) {
      auto grew = [](double from, double to) { return from > 0 && to > from * (1 + kMaxGrowth); };
      if (kUnderAsan) {
        if (r_.last.heap_bytes > r_.baseline->heap_bytes + kHeapSlackBytes &&
            grew(static_cast<double>(r_.baseline->heap_bytes), static_cast<double>(r_.last.heap_bytes)))
          r_.violations.push_back(
              fmt::format("heap in use grew from {:.2f} MB after the warm-up to {:.2f} MB (> {:.0f} %)",
                          r_.baseline->heap_bytes / 1e6, r_.last.heap_bytes / 1e6, kMaxGrowth * 100));
      } else if (grew(static_cast<double>(r_.baseline->rss_bytes), static_cast<double>(r_.last.rss_bytes))) {
        r_.violations.push_back(
            fmt::format("resident memory grew from {:.1f} MB after the warm-up to {:.1f} MB (> {:.0f} %)",
                        r_.baseline->rss_bytes / 1e6, r_.last.rss_bytes / 1e6, kMaxGrowth * 100));
      }
      if (grew(static_cast<double>(r_.baseline->fds), static_cast<double>(r_.last.fds)))
        r_.violations.push_back(fmt::format("open descriptors grew from {} after the warm-up to {} (> {:.0f} %)",
                                            r_.baseline->fds, r_.last.fds, kMaxGrowth * 100));
    }
    return r_;
  }

 private:
  Result<void> round(double total_s) {
    const int n = ++r_.rounds;
    const double left_s = total_s - secondsSince(t0_);
    const double length_s = std::min(o_.round_s, left_s);
    const std::string scenario_file = (scratch_.path / fmt::format("round-{}.xml", n)).string();
    std::ofstream(scenario_file) << randomScenario(menu_, rng_, 1000, o_.fault_every_ms, length_s * 1000);
    auto scenario = injection::loadScenario(scenario_file);
    if (!scenario) return fail(joined(scenario.error()));
    std::vector<plan::PropertySetting> settings;
    auto p = planned(o_, settings);
    if (!p) return p.error();
    engine::EngineOptions eo = engineOptions(o_);
    eo.property_settings = settings;
    eo.scenario = std::move(*scenario);
    eo.log_path = log_;
    eo.log_append = n > 1;
    eo.host_launch.args.push_back(fs::absolute(o_.profile).string());
    for (const auto& text : o_.sets) eo.host_launch.args.insert(eo.host_launch.args.end(), {"--set", text});
    eo.host_launch.args.insert(eo.host_launch.args.end(), {"--inject", scenario_file, "--log", log_});
    const std::uint64_t offset = n > 1 ? fileSize(log_) : 0;
    {
      auto e = engine::Engine::create(std::move(*p), std::move(eo));
      if (!e) return e.error();
      engine::Engine& engine = **e;
      if (auto started = engine.start(); !started) {
        engine.shutdown();
        return started.error();
      }
      const std::string reason = drive(engine, n, length_s);
      nlohmann::json stopping = log::schema::engine("stopping");
      stopping[log::schema::field::kReason] = reason;
      engine.log().write(std::move(stopping));
      engine.shutdown();
    }
    std::error_code ec;
    fs::remove(scenario_file, ec);  // the seed draws it again
    for (const auto& child : leftovers(5000ms))
      r_.violations.push_back(fmt::format("round {}: still running 5 s after its end: {}", n, child));
    audit(n, offset);
    sample(n);
    return {};
  }

  /// Runs one round until a component ends it, an emergency has held for a while, or its time
  /// is up; now and then presses the emergency stop as an operator would. Returns why it ended.
  std::string drive(engine::Engine& engine, int n, double length_s) {
    const auto start = Clock::now();
    const auto end = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(length_s));
    // One round in four, the operator stops the robot at a random moment.
    auto press = Clock::time_point::max();
    if (std::uniform_int_distribution<int>(0, 3)(rng_) == 0)
      press = start + std::chrono::milliseconds(std::uniform_int_distribution<int>(
                          1000, std::max(1000, static_cast<int>(length_s * 1000) - 500))(rng_));
    constexpr auto kNever =
        Clock::time_point::max();  // (std::optional<time_point> upsets GCC 12's -Wmaybe-uninitialized)
    auto latched_since = kNever;
    auto idle_since = kNever;
    auto last_progress = start;
    for (;;) {
      if (engine.waitForEnd(std::min(end, Clock::now() + 100ms))) return "ended by " + engine.runEnd()->component;
      const auto now = Clock::now();
      if (now >= end) return "round over";
      if (now >= press) {
        press = Clock::time_point::max();
        engine.emergencyStop("keel soak");
        ++r_.operator_emergencies;
      }
      if (engine.faultManager().emergencyLatched()) {
        if (latched_since == kNever) latched_since = now;
        if (now - latched_since >= 1500ms) return "emergency held";
      }
      const auto components = engine.components();
      if (std::none_of(components.begin(), components.end(),
                       [](const Component* c) { return c->state() == State::Active; })) {
        if (idle_since == kNever) idle_since = now;
        if (now - idle_since >= 1000ms) return "nothing running";
      } else {
        idle_since = kNever;
      }
      if (now - last_progress >= 1s) {
        last_progress = now;
        report(n);
      }
    }
  }

  void audit(int n, std::uint64_t offset) {
    const std::string text = readFrom(log_, offset);
    RoundAudit a = auditRound(text, r_.lines + 1);
    r_.lines += a.lines;
    r_.detected += a.detected;
    r_.emergencies += a.emergencies;
    r_.emergencies_reached += a.emergencies_reached;
    if (a.collisions) r_.collisions += *a.collisions;
    for (const auto& [kind, k] : a.by_kind) {
      KindCounts& total = r_.by_kind[kind];
      total.armed += k.armed;
      total.handled += k.handled;
      total.not_manifested += k.not_manifested;
      total.overtaken += k.overtaken;
    }
    for (auto& v : a.violations) r_.violations.push_back(fmt::format("round {}, {}", n, v));
  }

  void sample(int n) {
    r_.last = usageNow(true);  // between runs: nothing is allocating
    if (n == 1) r_.start = r_.last;
    if (!r_.baseline && secondsSince(t0_) >= o_.warmup_s) r_.baseline = r_.last;
    report(n);
  }

  void report(int n) {
    if (!progress_) return;
    SoakProgress p;
    p.round = n;
    p.elapsed_s = secondsSince(t0_);
    p.total_s = o_.minutes * 60;
    for (const auto& [kind, k] : r_.by_kind) {
      p.armed += k.armed;
      p.handled += k.handled;
    }
    p.violations = r_.violations.size();
    p.usage = usageNow();
    progress_(p);
  }

  const SoakOptions& o_;
  std::function<void(const SoakProgress&)> progress_;
  std::mt19937_64 rng_;
  ScratchDir scratch_;
  std::string log_;
  std::vector<Offer> menu_;
  Clock::time_point t0_;
  SoakResult r_;
};

}  // namespace

Result<SoakResult> runSoak(const SoakOptions& options, const std::function<void(const SoakProgress&)>& progress) {
  return Campaign(options, progress).run();
}

}  // namespace keel::soak
