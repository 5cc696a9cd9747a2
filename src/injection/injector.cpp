#include "injection/injector.hpp"

#include "log/schema.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <map>

#include "keel/hardware_driver.hpp"
#include "runtime/component_core.hpp"
#include "runtime/injection.hpp"

namespace keel::injection {

Injector::Injector(Scenario scenario, Find find, fault::FaultManager& manager, log::FaultLog& log, runtime::Warn warn)
    : scenario_(std::move(scenario)), find_(std::move(find)), manager_(manager), log_(log), warn_(std::move(warn)) {
  if (!warn_) warn_ = runtime::warnOnStderr;
}

Injector::~Injector() { stop(); }

Result<void> Injector::check(const runtime::Warn& warn, const std::function<bool(std::string_view)>& passive) const {
  std::string errors;
  for (const auto& f : scenario_.faults) {
    const std::string at = fmt::format("{}:{}", f.where.file, f.where.line);
    Component* c = find_(f.component);
    if (!c) {
      errors += fmt::format("{}: fault: no component '{}' in this run\n", at, f.component);
      continue;
    }
    if (f.hardware) continue;  // whether the component takes it shows when it is sent
    const auto& core = runtime::coreOf(*c);
    using runtime::InjectKind;
    if (f.kind == InjectKind::OutOfRange && !runtime::corruptiblePort(*c, f.port)) {
      errors += fmt::format("{}: fault: component '{}' has no numeric output data port{}\n", at, f.component,
                            f.port.empty() ? "" : fmt::format(" '{}'", f.port));
    }
    if (f.kind == InjectKind::Kill && dynamic_cast<runtime::ProcessTarget*>(c) == nullptr) {
      errors += fmt::format(
          "{}: fault: kill needs '{}' in a process of its own (<process> in its <subcomponent>); it runs in keel "
          "run's\n",
          at, f.component);
      continue;
    }
    if ((f.kind == InjectKind::Hang || f.kind == InjectKind::StallHeartbeat) && core.watch.heartbeat_ns == 0)
      warn(fmt::format("{}: fault: '{}' has no <heartbeat> in its fault_policy: this {} will not be detected", at,
                       f.component, f.kind_name));
    if (passive(f.component) && f.kind != InjectKind::OutOfRange && f.kind != InjectKind::Kill)
      warn(fmt::format("{}: fault: '{}' is passive (never executed): this {} will not fire", at, f.component,
                       f.kind_name));
  }
  if (!errors.empty()) {
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

void Injector::start(std::int64_t t0_ns) {
  if (scenario_.faults.empty() || thread_.joinable()) return;
  thread_ = std::thread([this, t0_ns] { run(t0_ns); });
}

void Injector::stop() {
  if (!thread_.joinable()) return;
  stop_.store(true, std::memory_order_release);
  signal_.notify();
  thread_.join();
}

void Injector::run(std::int64_t t0_ns) {
  struct Shot {
    std::int64_t t_ns;
    const ScheduledFault* fault;
  };
  std::vector<Shot> shots;
  for (const auto& f : scenario_.faults)
    for (int i = 0; i < f.repeat; ++i)
      shots.push_back({t0_ns + static_cast<std::int64_t>((f.at_ms + i * f.every_ms) * 1e6), &f});
  std::stable_sort(shots.begin(), shots.end(), [](const Shot& a, const Shot& b) { return a.t_ns < b.t_ns; });
  for (const Shot& s : shots) {
    while (!stop_.load(std::memory_order_acquire) && runtime::steadyNs() < s.t_ns)
      signal_.waitUntil(runtime::WakeSignal::Clock::time_point(std::chrono::nanoseconds(s.t_ns)));
    if (stop_.load(std::memory_order_acquire)) return;
    Component* c = find_(s.fault->component);
    if (!c) continue;
    const std::uint64_t id = manager_.nextId();
    if (s.fault->hardware) {
      injectHardware(*c, *s.fault, id);
      continue;
    }
    runtime::InjectArgs args{s.fault->port, s.fault->value, static_cast<std::int64_t>(s.fault->duration_ms * 1e6)};
    log_.write({{log::schema::field::kEvent, log::schema::event::kArmed},
                {log::schema::field::kFaultId, id},
                {log::schema::field::kComponent, s.fault->component},
                {log::schema::field::kKind, s.fault->kind_name}});
    if (runtime::arm(*c, s.fault->kind, id, args)) continue;
    if (s.fault->kind == runtime::InjectKind::Kill)
      warn_(fmt::format(
          "kill of '{}' at {} ms: no process of it was running then, or its last death was still being handled",
          s.fault->component, s.fault->at_ms));
    else if (s.fault->kind == runtime::InjectKind::StallHeartbeat)
      warn_(fmt::format("stall_heartbeat of '{}' at {} ms: it was not running (not Active) then", s.fault->component,
                        s.fault->at_ms));
  }
}

void Injector::injectHardware(Component& c, const ScheduledFault& f, std::uint64_t id) {
  const std::string command = f.command();
  const std::int64_t t_ns = log_.now();
  std::string outcome;
  try {
    auto* driver = dynamic_cast<HardwareDriver*>(&c);  // opt-in: keel/hardware_driver.hpp
    const ReturnCode rc = driver ? driver->onHardwareFault(command) : ReturnCode::Unsupported;
    if (!ok(rc)) outcome = toString(rc);
  } catch (const std::exception& e) {
    outcome = std::string("exception: ") + e.what();
  } catch (...) {
    outcome = "exception: unknown";
  }
  nlohmann::json record = log::schema::injected(id, f.component, t_ns);
  record[log::schema::field::kKind] = f.kind_name;
  record[log::schema::field::kDetail] = command;
  record[log::schema::field::kHardware] = true;
  if (!outcome.empty()) record[log::schema::field::kOutcome] = outcome;
  log_.write(std::move(record));
  if (!outcome.empty())
    warn_(fmt::format("{}:{}: hardware fault '{}' not taken by '{}': {}", f.where.file, f.where.line, command,
                      f.component, outcome));
}

}  // namespace keel::injection
