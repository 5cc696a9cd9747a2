#include "fault/fault_records.hpp"

#include <algorithm>

#include "log/schema.hpp"
#include "runtime/component_core.hpp"

namespace keel::fault {

void FaultRecords::writeChanges(const FaultReport& r, std::uint8_t action) {
  const std::string_view who = r.event.componentName();
  for (std::size_t i = 0; i < r.n_changes; ++i) {
    const FaultReport::Change& c = r.changes[i];
    if (c.action != action) continue;
    // The fault path changes only the object serving the name: the accused, or the alternative
    // switched in before it starts.
    const detail::ComponentCore& core = runtime::coreOf(*c.change.component);
    log_.write(log::schema::componentState(who, {core.class_name, core.alternative, true}, toString(c.change.from),
                                           toString(c.change.to), r.id, log_.sinceStart(c.change.t_ns)));
  }
}

void FaultRecords::logDetection(const FaultReport& r) {
  const std::string who(r.event.componentName());
  const std::string kind(toString(r.event.kind));
  if (r.injected_ns != 0) log_.write(log::schema::injected(r.id, who, log_.sinceStart(r.injected_ns)));
  nlohmann::json detected = log::schema::detected(r.id, who, kind, r.event.detailText(), r.detector.data(),
                                                  log_.sinceStart(r.event.t_ns));
  if (!r.event.measurementName().empty()) detected[log::schema::field::kMeasurement] = r.event.measurementName();
  log_.write(std::move(detected));
  writeChanges(r, FaultReport::kWithDetection);
  log_.write(log::schema::diagnosed(r.id, who, toString(r.severity),
                                    r.has_policy ? "fault_policy" : "none (contained, not recovered)",
                                    toString(r.scope), toString(r.first), log_.sinceStart(r.diagnosed_ns)));
  detections_.push_back({r.id, who, r.event.kind, r.event.t_ns, r.injected_ns});
  detection_count_.store(detections_.size(), std::memory_order_release);
  auto fc = std::find_if(counts_.begin(), counts_.end(),
                         [&](const FaultCount& c) { return c.component == who && c.kind == kind; });
  if (fc != counts_.end()) ++fc->count;
  else counts_.push_back({who, kind, std::string(r.event.detailText()), 1});
  handlings_.push_back({r.id,
                        who,
                        r.event.kind,
                        std::string(toString(r.severity)),
                        {},
                        false,
                        r.event.t_ns,
                        r.injected_ns,
                        0,
                        r.accused});
}

void FaultRecords::logReport(FaultReport& r) {
  r.describeEvent();
  const std::string who(r.event.componentName());
  std::lock_guard lock(mutex_);
  if (!r.detection_logged) {
    r.detection_logged = true;
    logDetection(r);
  }
  for (std::size_t i = r.logged_actions; i < r.n_actions; ++i) {  // what is new since last time
    const Action& a = r.actions[i];
    nlohmann::json rec = log::schema::action(r.id, who, toString(a.kind), a.ok, log_.sinceStart(a.t_ns));
    rec[log::schema::field::kDetail] = a.detail.data();
    if (a.kind == ActionKind::Replace && a.ok && r.alternative)
      rec[log::schema::field::kReplacement] = runtime::coreOf(*r.alternative).class_name;
    log_.write(std::move(rec));
    writeChanges(r, static_cast<std::uint8_t>(i));
  }
  auto hd = std::find_if(handlings_.rbegin(), handlings_.rend(), [&](const Handling& x) { return x.fault_id == r.id; });
  if (hd != handlings_.rend()) {  // the summary's view: every action of this fault so far
    std::string rebuilt;
    bool failed = false;
    for (std::size_t i = 0; i < r.n_actions; ++i) {
      if (!rebuilt.empty()) rebuilt += ", ";
      rebuilt += toString(r.actions[i].kind);
      if (!r.actions[i].ok) rebuilt += " (failed)";
      failed |= !r.actions[i].ok && r.actions[i].kind != ActionKind::Restore;
    }
    hd->actions = std::move(rebuilt);
    hd->failed = failed;
  }
  r.logged_actions = r.n_actions;
  if (changed_) changed_();
}

void FaultRecords::logRecovered(std::uint64_t id, std::string_view component, std::int64_t t_ns) {
  std::lock_guard lock(mutex_);
  auto hd = std::find_if(handlings_.rbegin(), handlings_.rend(), [&](const Handling& x) { return x.fault_id == id; });
  nlohmann::json rec = log::schema::recovered(id, component, log_.sinceStart(t_ns));
  if (hd != handlings_.rend()) {
    hd->recovered_ns = t_ns;
    rec[log::schema::field::kLatencyUs] = (t_ns - hd->detected_ns) / 1e3;
  }
  log_.write(std::move(rec));
  recovered_count_.fetch_add(1, std::memory_order_release);
  if (changed_) changed_();
}

void FaultRecords::logUndetected(std::uint64_t id, std::string_view component, std::int64_t injected_ns) {
  nlohmann::json rec = log::schema::injected(id, component, log_.sinceStart(injected_ns));
  rec[log::schema::field::kDetected] = false;
  log_.write(std::move(rec));
}

std::vector<FaultCount> FaultRecords::counts() const {
  std::lock_guard lock(mutex_);
  return counts_;
}

std::vector<Detection> FaultRecords::detections() const {
  std::lock_guard lock(mutex_);
  return detections_;
}

std::vector<Handling> FaultRecords::handlings() const {
  std::lock_guard lock(mutex_);
  return handlings_;
}

std::optional<Handling> FaultRecords::handling(std::uint64_t id) const {
  std::lock_guard lock(mutex_);
  for (auto it = handlings_.rbegin(); it != handlings_.rend(); ++it)
    if (it->fault_id == id) return *it;
  return std::nullopt;
}

}  // namespace keel::fault
